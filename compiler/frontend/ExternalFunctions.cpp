// Calls of external "C" functions (MLS 12.9): the function's declaration
// becomes a C wrapper with the IR's one signature (ir/External.h), built
// with the declaration's Include text and loaded into this process; each
// output element of the call is an IR External node. Arguments follow MLS
// 12.9.1: Real -> double, Integer, Boolean and enumerations -> int, arrays
// -> pointers to row-major data, outputs that are arguments -> pointers.
#include "frontend/ExternalLibraries.h"
#include "frontend/Flattener.h"
#include "ir/External.h"
#include "support/SourceManager.h"

#include <openssl/evp.h>

#include <dlfcn.h>

#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

namespace ldae::frontend {
namespace {

enum class CType { Double, Int };

const char *cName(CType t) { return t == CType::Double ? "double" : "int"; }

/// One argument of the C call.
struct CArg {
  bool output = false;
  CType type = CType::Double;
  bool array = false;
  size_t offset = 0, count = 1; // in the wrapper's in[] or out[]
};

/// The strings of annotation `key` of `fn` ("Include", "Library"): a
/// string or an array of strings.
std::vector<std::string> annotationStrings(const ast::ClassDef &fn,
                                           const std::string &key) {
  std::vector<std::string> out;
  for (const auto &ann : fn.annotations)
    for (const ast::Modifier &m : ann->args) {
      if (m.path.size() != 1 || m.path[0] != key || !m.mod || !m.mod->value)
        continue;
      const ast::Expr &v = *m.mod->value;
      if (v.kind == ast::ExprKind::String)
        out.push_back(v.text);
      else if (v.kind == ast::ExprKind::Array)
        for (const auto &e : v.ops)
          if (e && e->kind == ast::ExprKind::String)
            out.push_back(e->text);
    }
  return out;
}

std::string shortHash(const std::string &text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_Digest(text.data(), text.size(), digest, &len, EVP_sha256(), nullptr);
  static const char hex[] = "0123456789abcdef";
  std::string out;
  for (unsigned i = 0; i < 8 && i < len; ++i) {
    out += hex[digest[i] >> 4];
    out += hex[digest[i] & 15];
  }
  return out;
}

bool isCIdentifier(const std::string &s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0])))
    return false;
  for (char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
      return false;
  return true;
}

/// The C type of `c`: Real, Integer, Boolean, an enumeration, or a type
/// that names one through short classes.
std::optional<CType> externalCType(Flattener &flat, const ast::ClassDef &fn,
                                   const ast::Component &c) {
  ast::Name cur = c.typeName;
  const ast::ClassDef *scope = &fn;
  uint32_t file = fn.file;
  for (unsigned guard = 0; guard < 32; ++guard) {
    if (!cur.global && cur.parts.size() == 1) {
      if (cur.parts[0] == "Real")
        return CType::Double;
      if (cur.parts[0] == "Integer" || cur.parts[0] == "Boolean")
        return CType::Int;
    }
    const ast::ClassDef *cls =
        flat.classes().resolveClass(cur, scope, file, /*report=*/false);
    if (!cls)
      return std::nullopt;
    if (flat.enumerationOf(cls))
      return CType::Int;
    if (!cls->isShort)
      return std::nullopt;
    scope = cls->parent;
    file = cls->file;
    cur = cls->shortBase;
  }
  return std::nullopt;
}

} // namespace

std::optional<std::vector<Value>>
Flattener::externalCall(const ast::ClassDef &fn, Env &fenv) {
  const ast::ClassDef::ExternalClause &x = fn.external;
  SourceRange at{x.loc, x.length};
  if (x.language != "C") {
    report(DiagId::ErrUnsupported, at,
           {"external language \"" + x.language + "\""});
    return std::nullopt;
  }
  std::vector<const ast::Component *> outputs;
  for (const ast::Component &c : fn.components)
    if (c.prefix.causality == ast::Causality::Output)
      outputs.push_back(&c);
  auto component = [&](const std::string &name) -> const ast::Component * {
    for (const ast::Component &c : fn.components)
      if (c.name == name)
        return &c;
    return nullptr;
  };

  // The call as written, or the default mapping: the function's own name,
  // the inputs in order, the one output returned.
  std::string cFunction = x.function.empty() ? fn.name : x.function;
  const ast::Component *returned = nullptr;
  std::vector<const ast::Expr *> argExprs;
  std::vector<ast::ExprPtr> defaultArgs;
  if (x.function.empty()) {
    if (outputs.size() > 1) {
      report(DiagId::ErrUnsupported, at,
             {"an external function with several outputs and no external "
              "call written"});
      return std::nullopt;
    }
    returned = outputs.empty() ? nullptr : outputs[0];
    for (const ast::Component &c : fn.components)
      if (c.prefix.causality == ast::Causality::Input) {
        auto ref = std::make_unique<ast::Expr>();
        ref->kind = ast::ExprKind::Ref;
        ref->loc = c.loc;
        ref->parts.push_back({c.name, {}});
        argExprs.push_back(ref.get());
        defaultArgs.push_back(std::move(ref));
      }
  } else {
    if (x.output) {
      returned = x.output->parts.size() == 1 &&
                         x.output->parts[0].subscripts.empty()
                     ? component(x.output->parts[0].name)
                     : nullptr;
      if (!returned || returned->prefix.causality != ast::Causality::Output ||
          !returned->dims.empty()) {
        report(DiagId::ErrUnsupported,
               SourceRange{x.output->loc, x.output->length},
               {"an external call whose result is not a scalar output"});
        return std::nullopt;
      }
    }
    for (const auto &a : x.args)
      argExprs.push_back(a.get());
  }
  if (!isCIdentifier(cFunction)) {
    report(DiagId::ErrUnsupported, at,
           {"external function name '" + cFunction + "'"});
    return std::nullopt;
  }

  // Output slots in out[]: the returned value first, then output arguments.
  std::vector<ir::ExprRef> in;
  std::vector<CArg> args;
  std::map<const ast::Component *, size_t> outOffset;
  size_t numOut = 0;
  auto typeOf = [&](const ast::Component &c) -> std::optional<CType> {
    std::optional<CType> t = externalCType(*this, fn, c);
    if (!t)
      report(DiagId::ErrUnsupported, c.typeName.loc,
             {"external function arguments of type '" + c.typeName.str() +
              "'"});
    return t;
  };
  std::optional<CType> returnType;
  if (returned) {
    returnType = typeOf(*returned);
    if (!returnType)
      return std::nullopt;
    outOffset[returned] = numOut++;
  }
  Scope fscope{nullptr, &fn};
  for (const ast::Expr *e : argExprs) {
    CArg arg;
    const ast::Component *c =
        e->kind == ast::ExprKind::Ref && e->parts.size() == 1 &&
                e->parts[0].subscripts.empty()
            ? component(e->parts[0].name)
            : nullptr;
    if (c && c->prefix.causality == ast::Causality::Output) {
      std::optional<CType> t = typeOf(*c);
      if (!t)
        return std::nullopt;
      if (outOffset.count(c)) {
        report(DiagId::ErrUnsupported, SourceRange{e->loc, e->length},
               {"an output passed twice to an external function"});
        return std::nullopt;
      }
      arg.output = true;
      arg.type = *t;
      arg.array = !c->dims.empty();
      arg.count = fenv.find(c->name)->size();
      arg.offset = numOut;
      outOffset[c] = numOut;
      numOut += arg.count;
      args.push_back(arg);
      continue;
    }
    if (c) {
      std::optional<CType> t = typeOf(*c);
      if (!t)
        return std::nullopt;
      arg.type = *t;
    } else if (e->kind == ast::ExprKind::Call && e->text == "size") {
      arg.type = CType::Int; // MLS 12.9.1.1: size() is an int
    } else if (e->kind == ast::ExprKind::Number && e->number == std::floor(e->number)) {
      arg.type = CType::Int;
    }
    std::optional<Value> v = lower(*e, fscope, &fenv);
    if (!v)
      return std::nullopt;
    if (v->isString) {
      report(DiagId::ErrUnsupported, SourceRange{e->loc, e->length},
             {"string arguments of external functions"});
      return std::nullopt;
    }
    arg.array = !v->shape.empty();
    arg.offset = in.size();
    arg.count = v->size();
    in.insert(in.end(), v->elems.begin(), v->elems.end());
    args.push_back(arg);
  }
  for (const ast::Component *c : outputs)
    if (!outOffset.count(c)) {
      report(DiagId::ErrUnsupported, at,
             {"output '" + c->name + "' not passed to the external call"});
      return std::nullopt;
    }

  // The wrapper: converts, calls, stores every output.
  std::vector<std::string> includes = annotationStrings(fn, "Include");
  std::ostringstream src;
  for (const std::string &inc : includes)
    src << inc << "\n";
  std::string ret = returned ? cName(*returnType) : "void";
  if (includes.empty()) {
    src << "extern " << ret << " " << cFunction << "(";
    for (size_t i = 0; i < args.size(); ++i) {
      const CArg &a = args[i];
      src << (i ? ", " : "") << (a.output || !a.array ? "" : "const ")
          << cName(a.type) << (a.output || a.array ? " *" : "");
    }
    src << (args.empty() ? "void" : "") << ");\n";
  }
  std::string body;
  {
    std::ostringstream w;
    w << "(const double *in, double *out) {\n";
    std::string call = cFunction + "(";
    for (size_t i = 0; i < args.size(); ++i) {
      const CArg &a = args[i];
      std::string v = "a" + std::to_string(i);
      if (a.array || a.output) {
        w << "  " << cName(a.type) << " " << v << "[" << std::max<size_t>(1, a.count)
          << "];\n";
        if (!a.output)
          w << "  for (int i = 0; i < " << a.count << "; ++i) " << v << "[i] = ("
            << cName(a.type) << ")in[" << a.offset << " + i];\n";
      } else {
        w << "  " << cName(a.type) << " " << v << " = (" << cName(a.type) << ")in["
          << a.offset << "];\n";
      }
      call += (i ? ", " : "") + v;
    }
    call += ")";
    if (returned)
      w << "  out[0] = (double)" << call << ";\n";
    else
      w << "  " << call << ";\n";
    for (size_t i = 0; i < args.size(); ++i)
      if (args[i].output)
        w << "  for (int i = 0; i < " << args[i].count << "; ++i) out["
          << args[i].offset << " + i] = (double)a" << i << "[i];\n";
    w << "}\n";
    body = w.str();
  }
  std::string symbol = "ldaeext_" + cFunction + "_" + shortHash(src.str() + body);
  src << "void " << symbol << body;

  CBuild build;
  build.source = src.str();
  build.libraries = {"m"};
  auto handle = loadCBuild(build, opts_.cacheDir);
  if (!handle) {
    report(DiagId::ErrExternalBuild, at, {fn.name, handle.error()});
    return std::nullopt;
  }
  auto entry = reinterpret_cast<ir::ExternalEntry>(dlsym(*handle, symbol.c_str()));
  if (!entry) {
    report(DiagId::ErrExternalBuild, at, {fn.name, dlerror()});
    return std::nullopt;
  }
  ir::ExternalFunction f;
  f.name = fn.name;
  f.symbol = symbol;
  f.numInputs = in.size();
  f.numOutputs = numOut;
  f.entry = entry;
  uint32_t id = ir::registerExternal(f);

  std::vector<Value> results;
  for (const ast::Component *c : outputs) {
    Value v = *fenv.find(c->name);
    size_t base = outOffset[c];
    for (size_t k = 0; k < v.elems.size(); ++k)
      v.elems[k] = ctx().external(id, unsigned(base + k), in);
    results.push_back(std::move(v));
  }
  return results;
}

} // namespace ldae::frontend
