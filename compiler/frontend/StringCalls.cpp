// String(x, ...) (MLS 3.7.1.2), as the Modelica Standard Library builds its
// assert messages: "uMax (=" + String(uMax) + ") < uMin". The text is made
// when compiling where x has a value then: a constant, or a parameter
// (whose value at compile time the text shows; a message is text, not a
// result). In an assert's message a value known only at run time is a
// placeholder the runtime fills in when the assert fails
// (ir/MessageText.h); elsewhere it is refused, never printed as something
// else.
#include "frontend/Flattener.h"

#include "ir/MessageText.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace ldae::frontend {

namespace {

/// Whether `format` is one printf conversion Modelica allows
/// ("[flags][width][.precision]conversion", conversion one of f e E g G d i
/// x X o c), so it can be handed to snprintf safely.
bool safeFormat(const std::string &format, char &conversion) {
  if (format.empty() || format.size() > 16)
    return false;
  size_t i = 0;
  while (i < format.size() && std::string("-+ #0").find(format[i]) !=
                                  std::string::npos)
    ++i;
  while (i < format.size() && std::isdigit(static_cast<unsigned char>(format[i])))
    ++i;
  if (i < format.size() && format[i] == '.') {
    ++i;
    while (i < format.size() &&
           std::isdigit(static_cast<unsigned char>(format[i])))
      ++i;
  }
  if (i + 1 != format.size())
    return false;
  conversion = format[i];
  return std::string("feEgGdixXo").find(conversion) != std::string::npos;
}

} // namespace

std::optional<Value> Flattener::lowerStringCall(const ast::Expr &call,
                                                const Scope &scope, Env *env) {
  SourceRange where{call.loc, call.length};
  const ast::Expr *x = nullptr, *digits = nullptr, *minLength = nullptr,
                  *left = nullptr, *format = nullptr;
  for (size_t i = 0; i < call.args.size(); ++i) {
    const ast::Arg &a = call.args[i];
    const ast::Expr *v = a.value.get();
    if (a.name.empty() && i == 0)
      x = v;
    else if (a.name == "significantDigits" || (a.name.empty() && i == 1))
      digits = v;
    else if (a.name == "minimumLength" || (a.name.empty() && i == 2))
      minLength = v;
    else if (a.name == "leftJustified" || (a.name.empty() && i == 3))
      left = v;
    else if (a.name == "format")
      format = v;
    else {
      report(DiagId::ErrNamedArgBuiltin, SourceRange{v->loc, v->length},
             {"String", a.name});
      return std::nullopt;
    }
  }
  if (!x) {
    report(DiagId::ErrCallArgCount, where,
           {"String", "1 to 4", std::to_string(call.args.size())});
    return std::nullopt;
  }
  std::optional<Value> value = lower(*x, scope, env);
  if (!value)
    return std::nullopt;
  if (value->isString || !value->isScalar()) {
    report(DiagId::ErrExpectedScalar, SourceRange{x->loc, x->length},
           {"argument of 'String'",
            value->isString ? "a string" : describeShape(value->shape)});
    return std::nullopt;
  }
  std::optional<double> v = bindingValue(value->scalarExpr());
  if (!v && !messageValues_) {
    report(DiagId::ErrUnsupported, SourceRange{x->loc, x->length},
           {"String() of a value known only at run time"});
    return std::nullopt;
  }
  auto integerArg = [&](const ast::Expr *e, int64_t fallback,
                        const char *what) -> std::optional<int64_t> {
    return e ? evalInteger(*e, scope, env, what) : fallback;
  };
  std::optional<int64_t> sig = integerArg(digits, 6, "significantDigits");
  std::optional<int64_t> width = integerArg(minLength, 0, "minimumLength");
  std::optional<int64_t> leftJustified = integerArg(left, 1, "leftJustified");
  if (!sig || !width || !leftJustified)
    return std::nullopt;
  *width = std::clamp<int64_t>(*width, 0, 1000);
  *sig = std::clamp<int64_t>(*sig, 1, 17);
  char buf[128];
  std::optional<Value> f;
  char conversion = 0;
  if (format) {
    f = lower(*format, scope, env);
    if (!f)
      return std::nullopt;
    if (!f->isString || !safeFormat(f->str, conversion)) {
      report(DiagId::ErrUnsupported, SourceRange{format->loc, format->length},
             {"this format of String()"});
      return std::nullopt;
    }
  }
  if (!v) {
    messageValues_->push_back(value->scalarExpr());
    return Value::string(ir::messagePlaceholder(
        messageValues_->size() - 1,
        format ? "%" + f->str
               : "g" + std::to_string(*sig) + "," + std::to_string(*width) +
                     "," + (*leftJustified ? "1" : "0")));
  }
  if (format) {
    std::string spec = "%" + f->str;
    if (std::string("dixXo").find(conversion) != std::string::npos) {
      spec.insert(spec.size() - 1, "ll");
      std::snprintf(buf, sizeof buf, spec.c_str(),
                    static_cast<long long>(std::llround(*v)));
    } else {
      std::snprintf(buf, sizeof buf, spec.c_str(), *v);
    }
    return Value::string(buf);
  }
  // An integral value prints as an integer (Integer, Boolean and
  // enumeration arguments are integral here: their type is not kept).
  if (std::fabs(*v) < 1e15 && *v == std::floor(*v))
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(*v));
  else
    std::snprintf(buf, sizeof buf, "%.*g", static_cast<int>(*sig), *v);
  std::string text = buf;
  if (static_cast<int64_t>(text.size()) < *width) {
    std::string pad(static_cast<size_t>(*width) - text.size(), ' ');
    text = *leftJustified ? text + pad : pad + text;
  }
  return Value::string(text);
}

} // namespace ldae::frontend
