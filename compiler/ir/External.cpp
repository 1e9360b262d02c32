// The process-wide table of external function entries (External.h).
#include "ir/External.h"

#include <cassert>
#include <deque>
#include <mutex>
#include <vector>

namespace ldae::ir {
namespace {

struct Table {
  std::mutex mutex;
  std::deque<ExternalFunction> entries; // a deque: references stay valid
};

Table &table() {
  static Table t;
  return t;
}

} // namespace

uint32_t registerExternal(const ExternalFunction &f) {
  Table &t = table();
  std::lock_guard lock(t.mutex);
  for (size_t i = 0; i < t.entries.size(); ++i)
    if (t.entries[i].symbol == f.symbol)
      return static_cast<uint32_t>(i);
  t.entries.push_back(f);
  return static_cast<uint32_t>(t.entries.size() - 1);
}

bool anyExternal() {
  Table &t = table();
  std::lock_guard lock(t.mutex);
  return !t.entries.empty();
}

const ExternalFunction &externalFunction(uint32_t id) {
  Table &t = table();
  std::lock_guard lock(t.mutex);
  assert(id < t.entries.size());
  return t.entries[id];
}

bool isConstructorCall(ExprRef e) {
  return e && e->kind() == ExprKind::External &&
         externalFunction(e->externalId()).constructor;
}

double callExternal(uint32_t id, const double *in, unsigned output) {
  const ExternalFunction &f = externalFunction(id);
  std::vector<double> out(f.numOutputs > 0 ? f.numOutputs : 1, 0.0);
  f.entry(in, out.data());
  return out[output];
}

} // namespace ldae::ir
