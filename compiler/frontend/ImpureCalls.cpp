// Impure external functions (MLS 12.3): a call may return another value,
// or change something outside the model, each time it is made, so it is
// never an IR node (equal calls would be one node, and a node is evaluated
// whenever a backend likes). The Modelica Standard Library calls them
// while parameters get their values: Noise.GlobalSeed's `id_impure =
// initializeImpureRandom(seed)` stores the generator's state in C,
// `automaticGlobalSeed()` reads the clock. There, and only there
// (Flattener::ImpureContext), ldaec makes the call once when compiling,
// with arguments known then, and the outputs are constants: the
// parameters the arguments read become structural (a new value compiles
// again, and so calls again). A call at run time (at an event, from an
// equation) is refused: its count and order would be the backends'.
#include "frontend/Flattener.h"

#include <cmath>

namespace ldae::frontend {

std::optional<std::vector<Value>> Flattener::impureCall(
    const ast::ClassDef &fn, ir::ExternalEntry entry,
    const std::vector<ir::ExprRef> &in,
    const std::vector<const ast::Component *> &outputs,
    const std::map<const ast::Component *, size_t> &outOffset, size_t numOut,
    Env &fenv, SourceRange at) {
  // (Outside one, inlineCall refused the call where the model makes it.)
  std::vector<double> args(in.size(), 0.0);
  for (size_t i = 0; i < in.size(); ++i) {
    std::string evalError;
    std::optional<double> v = constantValue(in[i], &evalError);
    if (!v || !std::isfinite(*v)) {
      report(DiagId::ErrUnsupported, at,
             {"a call of impure function '" + fn.name +
              "' with arguments that change during the simulation" +
              (evalError.empty() ? std::string() : " (" + evalError + ")")});
      return std::nullopt;
    }
    args[i] = *v;
  }
  std::vector<double> out(std::max<size_t>(numOut, 1), 0.0);
  entry(args.data(), out.data());
  std::vector<Value> results;
  for (const ast::Component *c : outputs) {
    Value v = *fenv.find(c->name);
    size_t base = outOffset.at(c);
    for (size_t k = 0; k < v.elems.size(); ++k)
      v.elems[k] = ctx().constant(out[base + k]);
    results.push_back(std::move(v));
  }
  return results;
}

} // namespace ldae::frontend
