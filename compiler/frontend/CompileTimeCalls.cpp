// External calls made when compiling, whose results are constants.
//
// Impure functions (MLS 12.3): a call may return another value, or change
// something outside the model, each time it is made, so it is never an
// IR node (equal calls would be one node, and a node is evaluated whenever
// a backend likes). The Modelica Standard Library calls them while
// parameters get their values (Noise.GlobalSeed's `id_impure =
// initializeImpureRandom(seed)` stores the generator's state in C,
// `automaticGlobalSeed()` reads the clock, `readRealMatrix` a file) and
// at the start (`when initial() then success := writeRealMatrix(...)`).
// There, and only there (Flattener::ImpureContext), ldaec makes the call
// once when compiling, with arguments known then, and the outputs are
// constants: the parameters the arguments read become structural (a new
// value compiles, and so calls, again). A call at run time (at an event,
// from an equation) is refused where the model makes it (inlineCall):
// its count and order would be the backends'.
//
// Functions returning a String (MSL's Strings.substring, Streams.readLine):
// a String is a text known when compiling, so the call is made now too,
// with arguments known now.
#include "frontend/Flattener.h"
#include "support/ModelicaErrorMessage.h"

#include <cmath>

namespace ldae::frontend {

bool isInitialCall(const ast::Expr &e) {
  return e.kind == ast::ExprKind::Call && e.args.empty() &&
         e.parts.size() == 1 && e.parts[0].name == "initial";
}

std::optional<std::vector<double>>
Flattener::argumentsNow(const ast::ClassDef &fn,
                        const std::vector<ir::ExprRef> &in, SourceRange at) {
  std::vector<double> args(in.size(), 0.0);
  for (size_t i = 0; i < in.size(); ++i) {
    std::string evalError;
    std::optional<double> v = constantValue(in[i], &evalError);
    if (!v || !std::isfinite(*v)) {
      report(DiagId::ErrUnsupported, at,
             {"a call of '" + fn.name +
              "' (made when compiling) with arguments that change during "
              "the simulation" +
              (evalError.empty() ? std::string() : " (" + evalError + ")")});
      return std::nullopt;
    }
    args[i] = *v;
  }
  return args;
}

std::vector<Value> Flattener::constantOutputs(
    const std::vector<const ast::Component *> &outputs,
    const std::map<const ast::Component *, size_t> &outOffset,
    const std::vector<double> &out, Env &fenv) {
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

bool Flattener::succeeded(const ast::ClassDef &fn, SourceRange at) {
  std::string error = takeModelicaError();
  if (error.empty())
    return true;
  report(DiagId::ErrExternalFailed, at, {fn.name, error});
  return false;
}

std::optional<std::vector<Value>> Flattener::impureCall(
    const ast::ClassDef &fn, ir::ExternalEntry entry,
    ir::Model::CompileTimeCall made,
    const std::vector<ir::ExprRef> &in,
    const std::vector<const ast::Component *> &outputs,
    const std::map<const ast::Component *, size_t> &outOffset, size_t numOut,
    Env &fenv, SourceRange at) {
  std::optional<std::vector<double>> args = argumentsNow(fn, in, at);
  if (!args)
    return std::nullopt;
  std::vector<double> out(std::max<size_t>(numOut, 1), 0.0);
  entry(args->data(), out.data());
  if (!succeeded(fn, at))
    return std::nullopt;
  made.inputs = *args;
  made.outputs = unsigned(out.size());
  model_->compileTimeCalls.push_back(std::move(made));
  return constantOutputs(outputs, outOffset, out, fenv);
}

std::optional<std::vector<Value>> Flattener::stringCall(
    const ast::ClassDef &fn, ExternalStringEntry entry,
    const std::vector<ir::ExprRef> &in,
    const std::vector<const ast::Component *> &outputs,
    const ast::Component *returned,
    const std::map<const ast::Component *, size_t> &outOffset, size_t numOut,
    Env &fenv, SourceRange at) {
  if (fn.impure && impureContext_ == 0 && firingContext_ == 0) {
    report(DiagId::ErrUnsupported, at,
           {"a call of impure function '" + fn.name +
            "' outside a parameter's value or a when-clause"});
    return std::nullopt;
  }
  std::optional<std::vector<double>> args = argumentsNow(fn, in, at);
  if (!args)
    return std::nullopt;
  std::vector<double> out(std::max<size_t>(numOut, 1), 0.0);
  const char *text = entry(args->data(), out.data());
  if (!succeeded(fn, at))
    return std::nullopt;
  std::vector<const ast::Component *> numeric;
  for (const ast::Component *c : outputs)
    if (c != returned)
      numeric.push_back(c);
  std::vector<Value> values = constantOutputs(numeric, outOffset, out, fenv);
  std::vector<Value> results;
  size_t next = 0;
  for (const ast::Component *c : outputs)
    results.push_back(c == returned ? Value::string(text ? text : "")
                                    : std::move(values[next++]));
  return results;
}

} // namespace ldae::frontend
