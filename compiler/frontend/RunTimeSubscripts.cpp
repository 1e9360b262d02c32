// Subscripts known only at run time: `Tables.AndTable[x, y]` with x and y
// Integer or enumeration unknowns, as MSL's Digital library reads its logic
// tables. The selected dimension was kept whole; here each element of the
// result becomes a choice over it, `if i == 1 then a[1] else if i == 2 ...`,
// which every backend evaluates like any if-expression. The comparisons
// generate no events: the index is piecewise constant, changing only at
// events of its own. An index outside the dimension ends the run through an
// assert at the subscript (MLS 10.5: an index out of bounds is an error),
// never a silent pick of an edge element; inside an if-expression's branch
// the assert holds only where the branch is taken (`if i > 0 then a[i]
// else y0`, MSL's MultiSwitch).
#include "frontend/Flattener.h"

#include "ir/Traverse.h"

#include <unordered_set>

namespace ldae::frontend {

bool Flattener::isIntegerValued(ir::ExprRef index) {
  std::vector<ir::ExprRef> todo{index};
  std::unordered_set<ir::ExprRef> seen{index};
  while (!todo.empty()) {
    ir::ExprRef e = todo.back();
    todo.pop_back();
    switch (e->kind()) {
    case ir::ExprKind::Time:
      return false;
    case ir::ExprKind::Variable:
    case ir::ExprKind::Pre:
      if (!model_->variables[e->var()].isInteger &&
          !model_->variables[e->var()].isBoolean)
        return false;
      continue;
    case ir::ExprKind::Call:
      // integer(), floor() and ceil() are whole whatever they read
      // (TransportDelay's `LogicValues[integer(delay(xr, delayTime))]`).
      if (e->func() == ir::FuncKind::Floor || e->func() == ir::FuncKind::Ceil)
        continue;
      break;
    default:
      break;
    }
    for (ir::ExprRef op : e->operands())
      if (seen.insert(op).second)
        todo.push_back(op);
  }
  return true;
}

Value Flattener::selectAtRunTime(Value v,
                                 const std::vector<RunTimeSubscript> &runTime) {
  // Last axis first, so the earlier ones keep their positions.
  for (size_t r = runTime.size(); r-- > 0;) {
    const RunTimeSubscript &sub = runTime[r];
    int64_t outer = 1, inner = 1;
    for (size_t k = 0; k < sub.axis; ++k)
      outer *= v.shape[k];
    for (size_t k = sub.axis + 1; k < v.shape.size(); ++k)
      inner *= v.shape[k];
    const int64_t size = v.shape[sub.axis];
    Value out;
    out.shape = v.shape;
    out.shape.erase(out.shape.begin() + static_cast<std::ptrdiff_t>(sub.axis));
    out.elems.reserve(static_cast<size_t>(outer * inner));
    for (int64_t o = 0; o < outer; ++o)
      for (int64_t i = 0; i < inner; ++i) {
        auto element = [&](int64_t j) {
          return v.elems[static_cast<size_t>((o * size + j) * inner + i)];
        };
        // An empty dimension has no element to read: the range check
        // below fails wherever the read happens (MSL's MultiSwitch with
        // nu = 0 reads it only under a condition that is then false).
        if (size == 0) {
          out.elems.push_back(ctx().constant(0.0));
          continue;
        }
        ir::ExprRef chosen = element(size - 1);
        for (int64_t j = size - 1; j-- > 0;)
          chosen = ctx().ifThenElse(
              ctx().compare(ir::CompareKind::Eq, sub.index,
                            ctx().constant(static_cast<double>(j + 1)),
                            /*noEvent=*/true),
              element(j), chosen);
        out.elems.push_back(chosen);
      }
    indexInRange(sub, size);
    v = std::move(out);
  }
  return v;
}

void Flattener::indexInRange(const RunTimeSubscript &sub, int64_t size) {
  // Inside an if-expression's or an if-statement's branch the subscript is
  // used only where the branch is taken.
  ir::ExprRef guard = branchGuard_;
  if (statementGuard_)
    guard = guard ? ctx().logicalAnd(guard, statementGuard_) : statementGuard_;
  ir::Assert inRange;
  inRange.condition = ctx().logicalAnd(
      ctx().compare(ir::CompareKind::Ge, sub.index, ctx().one(), true),
      ctx().compare(ir::CompareKind::Le, sub.index,
                    ctx().constant(static_cast<double>(size)), true));
  if (guard)
    inRange.condition =
        ctx().logicalOr(ctx().logicalNot(guard), inRange.condition);
  inRange.message = "index out of range for '" + sub.what + "' of size " +
                    std::to_string(size);
  inRange.loc = sub.where.begin;
  // The same subscript lowered again (a loop body, an inlined function)
  // needs one check.
  std::vector<ir::Assert> &into = whenAsserts_ ? *whenAsserts_ : model_->asserts;
  for (const ir::Assert &a : into)
    if (a.condition == inRange.condition && a.message == inRange.message)
      return;
  into.push_back(std::move(inRange));
}

void Flattener::assignAtRunTime(
    const Value &value, const std::vector<int64_t> &shape,
    const std::vector<int64_t> &offsets,
    const std::vector<RunTimeSubscript> &runTime, Value &slot,
    const std::function<void(ir::ExprRef &, ir::ExprRef)> &write) {
  // `shape` keeps each run-time axis whole; `value` has them removed.
  std::vector<bool> chosenAtRunTime(shape.size(), false);
  for (const RunTimeSubscript &sub : runTime)
    chosenAtRunTime[sub.axis] = true;
  std::vector<int64_t> at(shape.size(), 0);
  for (size_t f = 0; f < offsets.size(); ++f) {
    // Element f of the selection: its position along each axis.
    int64_t rest = static_cast<int64_t>(f);
    for (size_t k = shape.size(); k-- > 0;) {
      at[k] = rest % shape[k];
      rest /= shape[k];
    }
    ir::ExprRef picked = nullptr;
    for (const RunTimeSubscript &sub : runTime) {
      ir::ExprRef here = ctx().compare(
          ir::CompareKind::Eq, sub.index,
          ctx().constant(static_cast<double>(at[sub.axis] + 1)), true);
      picked = picked ? ctx().logicalAnd(picked, here) : here;
    }
    size_t v = 0;
    for (size_t k = 0; k < shape.size(); ++k)
      if (!chosenAtRunTime[k])
        v = v * static_cast<size_t>(shape[k]) + static_cast<size_t>(at[k]);
    ir::ExprRef element = slot.elems[offsets[f]];
    ir::ExprRef assigned = value.shape.empty() ? value.elems[0] : value.elems[v];
    write(slot.elems[offsets[f]],
          element ? ctx().ifThenElse(picked, assigned, element) : nullptr);
  }
  for (const RunTimeSubscript &sub : runTime)
    indexInRange(sub, sub.size);
}

} // namespace ldae::frontend
