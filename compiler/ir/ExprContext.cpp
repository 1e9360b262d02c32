// Node creation and uniquing (hash-consing) for ExprContext, the leaf
// builders, and the per-node totality fact the simplifier relies on. The
// simplifying builders live in Arithmetic.cpp and Logic.cpp.
#include "ExprContextImpl.h"

#include <cassert>
#include <new>
#include <sys/mman.h>

namespace ldae::ir {

namespace {

size_t mix(size_t h, size_t v) {
  // 64-bit hash combine (boost-style with a better multiplier).
  h ^= v + 0x9e3779b97f4a7c15ull + (h << 12) + (h >> 4);
  return h * 0xff51afd7ed558ccdull;
}

/// See ExprContext::isTotal: finite and defined for all finite leaves.
/// `totalOf` gives the fact for the operands.
template <typename TotalOf> bool computeTotal(ExprRef e, TotalOf &&totalOf) {
  auto opsTotal = [&] {
    for (ExprRef op : e->operands())
      if (!totalOf(op))
        return false;
    return true;
  };
  switch (e->kind()) {
  case ExprKind::Constant:
    return std::isfinite(e->constant());
  case ExprKind::Parameter:
  case ExprKind::Variable:
  case ExprKind::Time:
  case ExprKind::Pre:
    return true;
  case ExprKind::Pow: {
    if (!opsTotal())
      return false;
    ExprRef base = e->operand(0), exponent = e->operand(1);
    return (exponent->isConstant() && isIntegral(exponent->constant()) &&
            exponent->constant() >= 0) ||
           (base->isConstant() && base->constant() > 0);
  }
  case ExprKind::External: // C code: no promise about its domain
    return false;
  case ExprKind::Call:
    switch (e->func()) {
    case FuncKind::Tan:
    case FuncKind::Asin:
    case FuncKind::Acos:
    case FuncKind::Log:
    case FuncKind::Log10:
    case FuncKind::Sqrt:
    case FuncKind::Mod:
      return false;
    default:
      return opsTotal();
    }
  default:
    return opsTotal();
  }
}

} // namespace

HugeBlock::HugeBlock(size_t bytes) : size_(bytes) {
  void *p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE,
                 MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED)
    throw std::bad_alloc(); // out of memory: nothing sensible to recover
  data_ = static_cast<char *>(p);
}

HugeBlock::~HugeBlock() {
  if (data_)
    munmap(data_, size_);
}

ExprContext::ExprContext() : impl_(std::make_unique<Impl>()) {}

ExprContext::~ExprContext() = default;

ExprRef ExprContext::intern(ExprKind kind, uint8_t sub, uint32_t index,
                            uint16_t order, double value,
                            std::span<const ExprRef> ops) {
  Expr probe;
  probe.kind_ = kind;
  probe.sub_ = sub;
  probe.index_ = index;
  probe.order_ = order;
  probe.value_ = value;
  probe.numOps_ = static_cast<uint32_t>(ops.size());
  probe.ops_ = ops.data();
  size_t h = mix(static_cast<size_t>(kind) << 8 | sub,
                 static_cast<size_t>(index) << 16 | order);
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  h = mix(h, bits);
  // Hash operands by creation id, never by address: iteration order of any
  // hash container keyed by nodes is then reproducible.
  for (ExprRef op : ops)
    h = mix(h, op->id());
  // Final avalanche: the table indexes by the low bits.
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  probe.hash_ = h;

  // Where the node is uniqued: a node with operands lives in the short user
  // list of its newest operand (the pivot) while that list is short, and in
  // the global table after. Building a DAG mostly combines recent nodes, so
  // the lists it searches are hot in cache while the table is not.
  Impl &im = *impl_;
  ExprRef pivot = nullptr;
  for (ExprRef op : ops)
    if (!pivot || op->id() > pivot->id())
      pivot = op;
  bool local = false;
  if (pivot) {
    for (ExprRef u = pivot->firstUser_; u; u = u->nextUser_)
      if (u->hash() == h && NodeEqual()(u, &probe))
        return u;
    local = pivot->userCount_ < kLocalUsers;
  }
  if (!local)
    if (ExprRef found = im.table.find(probe))
      return found;

  auto *node = new (im.arena.allocate(sizeof(Expr), alignof(Expr))) Expr();
  *node = probe;
  if (!ops.empty()) {
    auto *stored = static_cast<ExprRef *>(
        im.arena.allocate(ops.size() * sizeof(ExprRef), alignof(ExprRef)));
    std::copy(ops.begin(), ops.end(), stored);
    node->ops_ = stored;
  }
  assert(im.count < UINT32_MAX && "too many expression nodes");
  node->id_ = im.count++;
  node->total_ = computeTotal(node, [](ExprRef op) { return op->total_; });
  if (local) {
    node->nextUser_ = pivot->firstUser_;
    pivot->firstUser_ = node;
    ++pivot->userCount_;
  } else {
    im.table.insert(node);
  }
  return node;
}

ExprRef ExprContext::constant(double v) {
  // The commonest constants skip the table.
  Impl &im = *impl_;
  if (v == 0) { // one zero: -0 and +0 are the same constant
    if (!im.zero)
      im.zero = intern(ExprKind::Constant, 0, 0, 0, 0.0, {});
    return im.zero;
  }
  if (v == 1) {
    if (!im.one)
      im.one = intern(ExprKind::Constant, 0, 0, 0, 1.0, {});
    return im.one;
  }
  if (v == -1) {
    if (!im.minusOne)
      im.minusOne = intern(ExprKind::Constant, 0, 0, 0, -1.0, {});
    return im.minusOne;
  }
  return intern(ExprKind::Constant, 0, 0, 0, v, {});
}

ExprRef ExprContext::param(ParamId p) {
  return intern(ExprKind::Parameter, 0, p, 0, 0, {});
}

ExprRef ExprContext::var(VarId v, unsigned order) {
  assert(order <= UINT16_MAX && "derivative order too high");
  return intern(ExprKind::Variable, 0, v, static_cast<uint16_t>(order), 0, {});
}

ExprRef ExprContext::time() {
  if (!impl_->time)
    impl_->time = intern(ExprKind::Time, 0, 0, 0, 0, {});
  return impl_->time;
}

ExprRef ExprContext::pre(VarId v) {
  return intern(ExprKind::Pre, 0, v, 0, 0, {});
}

ExprRef ExprContext::external(uint32_t id, unsigned output,
                              std::span<const ExprRef> args, uint64_t serial) {
  return intern(ExprKind::External, 0, id, static_cast<uint16_t>(output),
                static_cast<double>(serial), args);
}

bool ExprContext::isTotal(ExprRef e) const { return e->total_; }

size_t ExprContext::size() const { return impl_->count; }

size_t ExprContext::memoryBytes() const {
  return impl_->arena.bytes() + impl_->table.bytes();
}

} // namespace ldae::ir
