// Calls of external "C" functions (MLS 12.9): the function's declaration
// becomes a C wrapper with the IR's one signature (ir/External.h), built
// with the declaration's Include text and loaded into this process; each
// output element of the call is an IR External node. Arguments follow MLS
// 12.9.1: Real -> double, Integer, Boolean and enumerations -> int, arrays
// -> pointers to row-major data, outputs that are arguments -> pointers.
#include "frontend/ExternalLibraries.h"
#include "frontend/ExternalObject.h"
#include "frontend/Flattener.h"
#include "ir/External.h"
#include "ir/Query.h"
#include "support/SourceManager.h"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

namespace ldae::frontend {
namespace {

enum class CType { Double, Int, String, Object };

const char *cName(CType t) {
  switch (t) {
  case CType::Double: return "double";
  case CType::Int: return "int";
  case CType::String: return "const char *";
  case CType::Object: return "void *";
  }
  return "double";
}

/// `s` as a C string literal.
std::string cLiteral(const std::string &s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += char(c);
    } else if (c < 32 || c >= 127) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\%03o", c);
      out += buf;
    } else {
      out += char(c);
    }
  }
  return out + "\"";
}

/// The C sources of the Modelica Standard Library's libraries (its
/// Resources/C-Sources/readme.txt); zlib is the system's.
const std::map<std::string, std::vector<std::string>> &knownLibraries() {
  static const std::map<std::string, std::vector<std::string>> libs = {
      {"ModelicaStandardTables",
       {"ModelicaStandardTables.c", "ModelicaStandardTablesUsertab.c"}},
      {"ModelicaIO", {"ModelicaIO.c"}},
      {"ModelicaMatIO", {"ModelicaMatIO.c", "snprintf.c"}},
      {"ModelicaExternalC",
       {"ModelicaFFT.c", "ModelicaInternal.c", "ModelicaRandom.c",
        "ModelicaStrings.c"}},
  };
  return libs;
}

/// One argument of the C call.
struct CArg {
  std::string literal; // a String argument: its text, known when compiling
  bool output = false;
  /// A protected array without a value (MSL's rawRealFFT `work`): scratch
  /// space for the C code, zeros in, nothing out (MLS 12.9.1).
  bool scratch = false;
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
      if (cur.parts[0] == "String")
        return CType::String;
    }
    const ast::ClassDef *cls =
        flat.classes().resolveClass(cur, scope, file, /*report=*/false);
    if (!cls)
      return std::nullopt;
    if (flat.enumerationOf(cls))
      return CType::Int;
    if (!cls->isShort && isExternalObject(*cls))
      return CType::Object;
    if (!cls->isShort)
      return std::nullopt;
    scope = cls->parent;
    file = cls->file;
    cur = cls->shortBase;
  }
  return std::nullopt;
}

} // namespace

namespace {

/// The directory of `fn`'s IncludeDirectory annotation (MLS 12.9.4), ""
/// when there is none on disk; an error for a URI ldaec cannot resolve.
Expected<std::string> libraryDirectory(const ast::ClassDef &fn,
                                       const SourceManager &sourceFiles) {
  // IncludeDirectory (MLS 12.9.4), default modelica://<top>/Resources/Include;
  // the MSL's points at Resources/C-Sources, where its libraries' sources
  // are too.
  const ast::ClassDef *top = &fn;
  while (top->parent)
    top = top->parent;
  std::vector<std::string> dirs = annotationStrings(fn, "IncludeDirectory");
  std::string uri = dirs.empty() ? "modelica://" + top->name + "/Resources/Include"
                                 : dirs[0];
  const std::string scheme = "modelica://";
  std::string rest = uri.substr(0, scheme.size()) == scheme
                         ? uri.substr(scheme.size())
                         : std::string();
  std::string first = rest.substr(0, rest.find('/'));
  if (rest.empty() || first != top->name) {
    if (dirs.empty())
      return std::string();
    return Error{"IncludeDirectory \"" + uri + "\" (only modelica://" +
                 top->name + "/... is)"};
  }
  std::filesystem::path file = sourceFiles.path(top->file);
  if (file.filename() != "package.mo")
    return std::string();
  std::filesystem::path dir =
      file.parent_path() / rest.substr(std::min(rest.size(), first.size() + 1));
  std::error_code ec;
  return std::filesystem::is_directory(dir, ec) ? dir.string() : std::string();
}

/// Builds and loads the C libraries of `fn`'s Library annotation that
/// ldaec compiles from sources, appending their files to `objects`; adds
/// the others to `wrapper` (-l). Returns an error text, "" when all is well.
std::string loadLibraries(const ast::ClassDef &fn, const std::string &sources,
                          CBuild &wrapper, const std::string &cacheDir,
                          std::vector<std::string> &objects) {
  std::vector<std::string> names = annotationStrings(fn, "Library");
  // ldaec's ModelicaUtilities first, then the libraries in reverse order:
  // each one's symbols are global before a library that calls them loads.
  std::vector<CBuild> builds;
  for (auto it = names.rbegin(); it != names.rend(); ++it) {
    const std::string &name = *it;
    if (name == "zlib" || name == "m") {
      wrapper.libraries.push_back(name == "zlib" ? "z" : "m");
      continue;
    }
    auto known = knownLibraries().find(name);
    if (known == knownLibraries().end() || sources.empty()) {
      wrapper.libraries.push_back(name); // a system library: -lname
      continue;
    }
    CBuild lib;
    for (const std::string &f : known->second)
      lib.files.push_back(sources + "/" + f);
    lib.includeDirs.push_back(sources);
    lib.defines.push_back("HAVE_ZLIB=1");
    // The library's own usertab stands in when the user gives none.
    lib.defines.push_back("DUMMY_FUNCTION_USERTAB=1");
    lib.libraries = {"z", "m"};
    builds.push_back(std::move(lib));
  }
  // Every wrapper reads its guard there, and any C code may call
  // ModelicaError (MLS 12.9.6).
  CBuild utilities;
  utilities.source = modelicaUtilitiesSource();
  builds.insert(builds.begin(), std::move(utilities));
  for (const CBuild &b : builds) {
    auto loaded = loadCBuild(b, cacheDir);
    if (!loaded)
      return loaded.error();
    objects.push_back(loaded->path);
  }
  return "";
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
    // A String result is a text known when compiling: no slot in out[]
    // (stringCall makes the call now).
    if (*returnType != CType::String)
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
      if (*t == CType::String || *t == CType::Object) {
        report(DiagId::ErrUnsupported, SourceRange{e->loc, e->length},
               {"string or external object outputs passed as arguments"});
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
    if (c && c->prefix.causality == ast::Causality::None) {
      const Value *v = fenv.find(c->name);
      if (v && !v->isString &&
          std::any_of(v->elems.begin(), v->elems.end(),
                      [](ir::ExprRef x) { return !x; })) {
        std::optional<CType> t = typeOf(*c);
        if (!t)
          return std::nullopt;
        arg.type = *t;
        arg.scratch = true;
        arg.array = !c->dims.empty();
        arg.count = v->size();
        args.push_back(arg);
        continue;
      }
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
    if (v->isString != (arg.type == CType::String) ||
        (arg.type == CType::Object && !v->shape.empty())) {
      report(DiagId::ErrUnsupported, SourceRange{e->loc, e->length},
             {"this argument of an external function"});
      return std::nullopt;
    }
    if (v->isString) {
      arg.literal = v->str;
      args.push_back(arg);
      continue;
    }
    arg.array = !v->shape.empty();
    arg.offset = in.size();
    arg.count = v->size();
    in.insert(in.end(), v->elems.begin(), v->elems.end());
    args.push_back(arg);
  }
  for (const ast::Component *c : outputs)
    if (!outOffset.count(c) && c != returned) {
      report(DiagId::ErrUnsupported, at,
             {"output '" + c->name + "' not passed to the external call"});
      return std::nullopt;
    }

  // Run-time impure calls (FiringContext): the call site's own wrapper
  // keeps its last inputs and outputs, and a call with the same inputs
  // returns them without calling again, so the evaluations of one event
  // (its iterations, the readings around it) make one call. The inputs
  // end with the previous impure call's first output, which orders the
  // calls as written, and the time, which makes each event's call new.
  // A String result is a text known when compiling, so an impure function
  // returning one is called when compiling even in a when-clause, with
  // arguments known then (stringCall: MSL's Files.fullPathName of a file
  // name the model gives).
  const bool atRunTime = fn.impure && impureContext_ == 0 &&
                         !(returned && *returnType == CType::String);
  uint64_t site = 0;
  if (atRunTime) {
    site = ++impureSites_;
    in.push_back(impureToken_ ? impureToken_ : ctx().constant(0));
    in.push_back(ctx().time());
  }

  // The wrapper: converts, calls, stores every output.
  std::vector<std::string> includes = annotationStrings(fn, "Include");
  std::ostringstream src;
  src << "#include <setjmp.h>\n#include <stdint.h>\n#include <stdlib.h>\n"
      << "#include <string.h>\n"
      << "extern __thread jmp_buf *ldae_modelica_guard;\n";
  const size_t outSlots = std::max<size_t>(numOut, 1);
  if (atRunTime)
    src << "/* run-time call site " << site << " */\n"
        << "static __thread int memo_valid;\n"
        << "static __thread double memo_in[" << std::max<size_t>(in.size(), 1)
        << "], memo_out[" << outSlots << "];\n";
  for (const std::string &inc : includes)
    src << inc << "\n";
  std::string ret = returned ? cName(*returnType) : "void";
  if (includes.empty()) {
    src << "extern " << ret << " " << cFunction << "(";
    for (size_t i = 0; i < args.size(); ++i) {
      const CArg &a = args[i];
      src << (i ? ", " : "")
          << (a.output || a.scratch || !a.array || a.type == CType::String
                  ? ""
                  : "const ")
          << cName(a.type) << (a.output || a.array ? " *" : "");
    }
    src << (args.empty() ? "void" : "") << ");\n";
  }
  std::string body;
  bool stringResult = returned && *returnType == CType::String;
  {
    std::ostringstream w;
    w << "(const double *in, double *out) {\n";
    if (atRunTime)
      w << "  if (memo_valid && memcmp(memo_in, in, sizeof memo_in) == 0) {\n"
        << "    memcpy(out, memo_out, sizeof memo_out);\n    return;\n  }\n"
        << "  out[0] = 0.0;\n";
    std::string call = cFunction + "(";
    for (size_t i = 0; i < args.size(); ++i) {
      const CArg &a = args[i];
      std::string v = "a" + std::to_string(i);
      if (a.type == CType::String) {
        w << "  const char *" << v << " = " << cLiteral(a.literal) << ";\n";
      } else if (a.type == CType::Object) {
        w << "  void *" << v << " = (void *)(uintptr_t)in[" << a.offset
          << "];\n";
      } else if (a.scratch) {
        w << "  " << cName(a.type) << " *" << v << " = calloc("
          << std::max<size_t>(1, a.count) << ", sizeof(" << cName(a.type)
          << "));\n  if (!" << v << ") {\n"
          << "    for (int i = 0; i < " << numOut
          << "; ++i) out[i] = 0.0 / 0.0;\n    return"
          << (stringResult ? " 0" : "") << ";\n  }\n";
      } else if (a.array || a.output) {
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
    // A ModelicaError in the call jumps back here (ModelicaUtilitiesSource):
    // every output NaN, the message kept for the report; a call without
    // outputs too (its one slot, which a run-time impure call's successor
    // reads: a failed removeFile is no success).
    w << "  jmp_buf guard;\n  jmp_buf *outer = ldae_modelica_guard;\n"
      << "  if (setjmp(guard)) {\n    ldae_modelica_guard = outer;\n"
      << "    for (int i = 0; i < " << outSlots
      << "; ++i) out[i] = 0.0 / 0.0;\n    return"
      << (stringResult ? " 0" : "") << ";\n  }\n"
      << "  ldae_modelica_guard = &guard;\n";
    if (stringResult)
      w << "  const char *result = " << call << ";\n";
    else if (returned && *returnType == CType::Object)
      w << "  out[0] = (double)(uintptr_t)" << call << ";\n";
    else if (returned)
      w << "  out[0] = (double)" << call << ";\n";
    else
      w << "  " << call << ";\n";
    w << "  ldae_modelica_guard = outer;\n";
    for (size_t i = 0; i < args.size(); ++i)
      if (args[i].scratch)
        w << "  free(a" << i << ");\n";
    for (size_t i = 0; i < args.size(); ++i)
      if (args[i].output)
        w << "  for (int i = 0; i < " << args[i].count << "; ++i) out["
          << args[i].offset << " + i] = (double)a" << i << "[i];\n";
    if (atRunTime)
      w << "  memcpy(memo_in, in, sizeof memo_in);\n"
        << "  memcpy(memo_out, out, sizeof memo_out);\n  memo_valid = 1;\n";
    if (stringResult)
      w << "  return result;\n";
    w << "}\n";
    body = w.str();
  }
  std::string symbol = "ldaeext_" + cFunction + "_" + sha256Hex(src.str() + body).substr(0, 16);
  src << (stringResult ? "const char *" : "void ") << symbol << body;

  CBuild build;
  build.source = src.str();
  build.libraries = {"m"};
  Expected<std::string> sources = libraryDirectory(fn, diags_.sources());
  if (!sources) {
    report(DiagId::ErrUnsupported, at, {sources.error()});
    return std::nullopt;
  }
  if (!sources->empty())
    build.includeDirs.push_back(*sources);
  std::vector<std::string> objects;
  if (std::string e =
          loadLibraries(fn, *sources, build, opts_.cacheDir, objects);
      !e.empty()) {
    report(DiagId::ErrExternalBuild, at, {fn.name, e});
    return std::nullopt;
  }
  auto loaded = loadCBuild(build, opts_.cacheDir);
  if (!loaded) {
    report(DiagId::ErrExternalBuild, at, {fn.name, loaded.error()});
    return std::nullopt;
  }
  objects.push_back(loaded->path);
  auto entry =
      reinterpret_cast<ir::ExternalEntry>(dlsym(loaded->handle, symbol.c_str()));
  if (!entry) {
    report(DiagId::ErrExternalBuild, at, {fn.name, dlerror()});
    return std::nullopt;
  }
  if (stringResult)
    return stringCall(fn, reinterpret_cast<ExternalStringEntry>(entry), in,
                      outputs, returned, outOffset, numOut, fenv, at);
  if (fn.impure && !atRunTime)
    return impureCall(fn, entry, {symbol, objects, {}, 0}, in, outputs,
                      outOffset, numOut, fenv, at);
  ir::ExternalFunction f;
  f.name = fn.name;
  f.symbol = symbol;
  f.numInputs = in.size();
  f.numOutputs = atRunTime ? outSlots : numOut;
  f.impure = atRunTime;
  f.entry = entry;
  f.objects = std::move(objects);
  f.constructor = fn.name == "constructor" && fn.parent &&
                  isExternalObject(*fn.parent);
  if (!externalCallFits(fn, f, at))
    return std::nullopt;
  uint32_t id = ir::registerExternal(f);

  std::vector<Value> results;
  for (const ast::Component *c : outputs) {
    Value v = *fenv.find(c->name);
    size_t base = outOffset[c];
    for (size_t k = 0; k < v.elems.size(); ++k)
      v.elems[k] = ctx().external(id, unsigned(base + k), in, site);
    results.push_back(std::move(v));
  }
  if (atRunTime) {
    impureToken_ = ctx().external(id, 0, in, site);
    impureTokenSite_ = site;
  }
  return results;
}

bool Flattener::externalCallFits(const ast::ClassDef &fn,
                                 const ir::ExternalFunction &f,
                                 SourceRange at) {
  // Each output is a node of its own reading every input, and the code
  // generators call the function once per output: MSL's realFFT of a
  // 5000-sample buffer to 400 amplitudes took more than 12 GB to compile.
  constexpr double kMaxWork = 1e6;
  if (double(f.numInputs) * double(f.numOutputs) <= kMaxWork)
    return true;
  report(DiagId::ErrUnsupported, at,
         {"a call of '" + fn.name + "' with " + std::to_string(f.numInputs) +
          " inputs and " + std::to_string(f.numOutputs) +
          " outputs (ldaec calls external code once per output, and refuses "
          "more than 10^6 inputs times outputs)"});
  return false;
}

void Flattener::keepImpureCalls(ir::WhenClause &clause) {
  if (!impureToken_)
    return;
  std::vector<ir::ExprRef> roots;
  for (const ir::Equation &e : clause.equations)
    roots.push_back(e.residual);
  for (ir::ExprRef n : ir::topologicalOrder(roots))
    if (n->kind() == ir::ExprKind::External &&
        static_cast<uint64_t>(n->constant()) == impureTokenSite_)
      return;
  // A call made for what it does (a file written, its result unused): a
  // value of the compiler's own, assigned by the clause, reads it.
  ir::Variable v;
  v.name = "$impure" + std::to_string(impureTokenSite_);
  v.loc = clause.loc;
  v.isDiscrete = v.generated = true;
  ir::ExprRef made = ctx().var(model_->addVariable(std::move(v)));
  ir::Equation e;
  e.residual = ctx().sub(made, impureToken_);
  e.loc = clause.loc;
  e.text = "the impure calls of the when-clause";
  clause.equations.push_back(std::move(e));
  clause.targets.push_back(made);
}

} // namespace ldae::frontend
