// A pass, and where the runner keeps the typed results passes hand each
// other. A pass derives from TypedPass, whose arguments list what it reads,
// what it updates in place and what it produces; its `runOn` takes exactly
// those, so the signature shows the dependency order, and the pipeline
// test checks that every result a pass reads was produced before it.
//
//   class PantelidesPass
//       : public TypedPass<PantelidesPass, Reads<MatchingResult>, Updates<>,
//                          Produces<IndexReduction>> { ...
//     bool runOn(PassContext &, const MatchingResult &, IndexReduction &);
//
// Internal to compiler/passes.
#pragma once

#include "passes/PassContext.h"

#include <iosfwd>
#include <memory>
#include <typeindex>
#include <unordered_map>
#include <utility>
#include <vector>

namespace ldae::passes {

/// One id per entry of Passes.def, in its order.
enum class PassId {
#define PASS(Id, Name, Summary, Create) Id,
#include "passes/Passes.def"
};

/// The table entry of `id` (name and summary).
const PassInfo &passInfo(PassId id);

/// The typed results of the passes run so far, one of each type.
class ResultStore {
public:
  template <typename T> bool has() const {
    return results_.count(std::type_index(typeid(T))) != 0;
  }
  /// The result an earlier pass produced; a pipeline that reads a result
  /// before producing it is a bug in the pipeline: aborts.
  template <typename T> T &get() {
    auto it = results_.find(std::type_index(typeid(T)));
    if (it == results_.end())
      missing(typeid(T));
    return *static_cast<T *>(it->second.get());
  }
  /// A fresh result, replacing any earlier one of its type.
  template <typename T> T &make() {
    auto p = std::make_shared<T>();
    T &ref = *p;
    results_[std::type_index(typeid(T))] = std::move(p);
    return ref;
  }

private:
  [[noreturn]] static void missing(const std::type_info &type);
  std::unordered_map<std::type_index, std::shared_ptr<void>> results_;
};

class Pass {
public:
  explicit Pass(PassId id) : id_(id) {}
  virtual ~Pass() = default;

  PassId id() const { return id_; }
  /// The name in Passes.def (`--print-after`, `--time-passes`).
  const char *name() const { return passInfo(id_).name; }

  /// False after reporting an error that stops the pipeline.
  virtual bool run(PassContext &ctx, ResultStore &results) = 0;
  /// The result types it reads (updated ones included) and produces
  /// (updated ones included).
  virtual std::vector<std::type_index> reads() const = 0;
  virtual std::vector<std::type_index> produces() const = 0;
  /// What `--print-after` shows: the index-1 system once it exists, the
  /// model before.
  virtual void print(PassContext &ctx, ResultStore &results,
                     std::ostream &out) const;

private:
  PassId id_;
};

template <typename... T> struct Reads {};
template <typename... T> struct Updates {};
template <typename... T> struct Produces {};

template <typename Derived, typename R, typename U, typename P>
class TypedPass;

/// Calls `Derived::runOn(ctx, const R&..., U&..., P&...)` with the stored
/// results: the R and U of earlier passes, fresh P.
template <typename Derived, typename... R, typename... U, typename... P>
class TypedPass<Derived, Reads<R...>, Updates<U...>, Produces<P...>>
    : public Pass {
public:
  using Pass::Pass;
  bool run(PassContext &ctx, ResultStore &results) final {
    return static_cast<Derived &>(*this).runOn(
        ctx, std::as_const(results.get<R>())..., results.get<U>()...,
        results.make<P>()...);
  }
  std::vector<std::type_index> reads() const final {
    return {std::type_index(typeid(R))..., std::type_index(typeid(U))...};
  }
  std::vector<std::type_index> produces() const final {
    return {std::type_index(typeid(U))..., std::type_index(typeid(P))...};
  }
};

} // namespace ldae::passes
