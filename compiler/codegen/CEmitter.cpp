// The C99 printer over the code plan: one self-contained file (the C
// standard library and the inlined ldae/model.h only) defining every plan
// function with its C ABI signature, the tables of the model and a filled
// `const ldae_model ldae_model_<name>`; optionally a `main` handing the
// model to the runtime's ldae_main (ldae/run.h, inlined; libldaert). Same
// nodes, same order, same error bits as the LLVM emitter and the
// interpreter.
#include "codegen/CEmitter.h"

#include "codegen/EmbeddedText.h"
#include "codegen/LlvmEmitter.h"
#include "support/CLiteral.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace ldae::codegen {

using ir::CompareKind;
using ir::FuncKind;

namespace {

std::string number(double v) { return cDoubleLiteral(v); }

std::string quote(const std::string &s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

const char *cCompare(CompareKind c) {
  static const char *ops[] = {"<", "<=", ">", ">=", "==", "!="};
  return ops[unsigned(c)];
}

/// Prints the statements of one chunk.
class ChunkPrinter {
public:
  /// `inLoop`: `fn` is a loop body; load and store indices name the index
  /// columns c0, c1, ... declared by the loop.
  /// `sym`: the plan function's symbol, whose `<sym>_reduce<k>` functions
  /// Reduce nodes call.
  ChunkPrinter(std::ostream &os, const PlanFunction &fn, const PlanChunk &c,
               std::string sym, bool inLoop = false)
      : os_(os), fn_(fn), chunk_(c), sym_(std::move(sym)), inLoop_(inLoop) {}

  void print() {
    uint32_t next = chunk_.storeBegin;
    for (uint32_t k = chunk_.nodeBegin; k < chunk_.nodeEnd; ++k) {
      const PlanNode &n = fn_.nodes[k];
      if (!isLeaf(n.op)) {
        printNode(k);
        if (fn_.spill[k] >= 0) {
          os_ << "  tmp[" << fn_.spill[k] << "] = v" << k << ";\n";
          if (n.mayFail)
            os_ << "  tmp[" << fn_.spill[k] + 1 << "] = e" << k << ";\n";
        }
      }
      for (; next < chunk_.storeEnd && fn_.stores[next].after <= k; ++next)
        printStore(fn_.stores[next]);
    }
    for (; next < chunk_.storeEnd; ++next)
      printStore(fn_.stores[next]);
  }

  /// The C expression of node k's value and of its error bit.
  std::string valueOf(uint32_t k) const { return ref(k); }
  std::string errorOf(uint32_t k) const { return err(k); }

private:
  void printStore(const PlanStore &s) {
    os_ << "  out" << int(s.array) << "[" << index(s.index) << "] = "
        << ref(s.node) << ";\n";
    if (!fn_.nodes[s.node].mayFail)
      return;
    os_ << "  if (!rc && " << err(s.node) << ") rc = ";
    if (inLoop_)
      os_ << "(int)c" << s.row << " + 1;\n";
    else
      os_ << s.row + 1 << ";\n";
  }

  std::string index(int64_t i) const {
    return (inLoop_ ? "c" : "") + std::to_string(i);
  }

  bool inChunk(uint32_t k) const {
    return k >= chunk_.nodeBegin && k < chunk_.nodeEnd;
  }
  std::string ref(uint32_t k) const {
    const PlanNode &n = fn_.nodes[k];
    switch (n.op) {
    case OpCode::Const: return number(n.value);
    case OpCode::LoadY: return "y[" + index(n.index) + "]";
    case OpCode::LoadYp: return "yp[" + index(n.index) + "]";
    case OpCode::LoadP: return "p[" + index(n.index) + "]";
    case OpCode::Time: return "t";
    case OpCode::Cj: return "cj";
    default:
      if (inChunk(k))
        return "v" + std::to_string(k);
      return "tmp[" + std::to_string(fn_.spill[k]) + "]";
    }
  }
  std::string err(uint32_t k) const {
    if (!fn_.nodes[k].mayFail)
      return "0";
    if (inChunk(k))
      return "e" + std::to_string(k);
    return "(tmp[" + std::to_string(fn_.spill[k] + 1) + "] != 0.0)";
  }

  void printNode(uint32_t k) {
    const PlanNode &n = fn_.nodes[k];
    std::string a = ref(n.a);
    std::string b = numOperands(n.op) >= 2 ? ref(n.b) : "";
    std::string v = "v" + std::to_string(k);
    std::string expr, check;
    if (n.op == OpCode::Reduce) {
      std::string e = "e" + std::to_string(k);
      if (n.mayFail)
        os_ << "  int " << e << " = " << err(n.a) << ";\n";
      os_ << "  const double " << v << " = " << sym_ << "_reduce" << n.index
          << "(t, y, yp, p, cj, " << a << ", " << (n.mayFail ? "&" + e : "0")
          << ");\n";
      return;
    }
    if (n.op == OpCode::ExtCall) {
      printExternalCall(k);
      return;
    }
    switch (n.op) {
    case OpCode::ExtArg: expr = a; break;
    case OpCode::Add: expr = a + " + " + b; break;
    case OpCode::Sub: expr = a + " - " + b; break;
    case OpCode::Mul: expr = a + " * " + b; break;
    case OpCode::Div:
      expr = a + " / " + b;
      check = b + " == 0.0";
      break;
    case OpCode::Neg: expr = "-" + a; break;
    case OpCode::PowInt: {
      std::string result, base = a;
      unsigned tmpCount = 0;
      auto temp = [&](const std::string &e) {
        std::string name = v + "_" + std::to_string(tmpCount++);
        os_ << "  const double " << name << " = " << e << ";\n";
        return name;
      };
      for (PowIntStep s : powIntSteps(n.index)) {
        if (s.multiplyResult)
          result = result.empty() ? base : temp(result + " * " + base);
        if (s.squareBase)
          base = temp(base + " * " + base);
      }
      expr = result;
      break;
    }
    case OpCode::Pow:
      expr = "pow(" + a + ", " + b + ")";
      check = "(" + a + " < 0.0 && floor(" + b + ") != " + b + ") || (" + a +
              " == 0.0 && " + b + " < 0.0)";
      break;
    case OpCode::Sqrt:
      expr = "sqrt(" + a + ")";
      check = a + " < 0.0";
      break;
    case OpCode::Func1: {
      auto f = FuncKind(n.sub);
      if (f == FuncKind::Sign)
        expr = "(double)(" + a + " > 0.0) - (double)(" + a + " < 0.0)";
      else
        expr = std::string(cMathName(f)) + "(" + a + ")";
      if (f == FuncKind::Log || f == FuncKind::Log10)
        check = "!(" + a + " > 0.0)";
      else if (f == FuncKind::Asin || f == FuncKind::Acos)
        check = "fabs(" + a + ") > 1.0";
      break;
    }
    case OpCode::Func2:
      switch (FuncKind(n.sub)) {
      case FuncKind::Atan2: expr = "atan2(" + a + ", " + b + ")"; break;
      case FuncKind::Min: expr = a + " < " + b + " ? " + a + " : " + b; break;
      case FuncKind::Max: expr = a + " > " + b + " ? " + a + " : " + b; break;
      case FuncKind::Mod:
        expr = a + " - floor(" + a + " / " + b + ") * " + b;
        check = b + " == 0.0";
        break;
      default: assert(false && "not a binary built-in");
      }
      break;
    case OpCode::Select:
      expr = a + " != 0.0 ? " + b + " : " + ref(n.c);
      break;
    case OpCode::Compare:
      expr = "(double)(" + a + " " + cCompare(CompareKind(n.sub)) + " " + b + ")";
      break;
    case OpCode::And: expr = "(double)(" + a + " != 0.0 && " + b + " != 0.0)"; break;
    case OpCode::Or: expr = "(double)(" + a + " != 0.0 || " + b + " != 0.0)"; break;
    case OpCode::Not: expr = "(double)(" + a + " == 0.0)"; break;
    default: assert(false && "leaf in printNode");
    }
    os_ << "  const double " << v << " = " << expr << ";\n";
    if (!n.mayFail)
      return;
    std::string e;
    if (n.op == OpCode::Select) {
      e = err(n.a) + " | (" + a + " != 0.0 ? " + err(n.b) + " : " +
          err(n.c) + ")";
    } else if (n.op == OpCode::And || n.op == OpCode::Or) {
      e = err(n.a) + " | (" + a + (n.op == OpCode::And ? " != " : " == ") +
          "0.0 && " + err(n.b) + ")";
    } else {
      e = check.empty() ? "0" : "(" + check + ")";
      for (unsigned i = 0; i < numOperands(n.op); ++i)
        if (fn_.nodes[n.operand(i)].mayFail)
          e += " | " + err(n.operand(i));
    }
    os_ << "  const int e" << k << " = " << e << ";\n";
  }

  /// `void symbol(const double *in, double *out)` on local arrays; as the
  /// JIT does, only where its guard holds when it has one (sub = 1: a
  /// branch taken), tables keeping state between calls. NaN is an error.
  void printExternalCall(uint32_t k) {
    const PlanNode &n = fn_.nodes[k];
    const PlanExternal &x = fn_.externals[n.index];
    std::vector<uint32_t> args = externalArguments(fn_.nodes, k);
    std::string v = "v" + std::to_string(k);
    os_ << "  double " << v << " = 0.0;\n";
    os_ << (n.sub == 1 ? "  if (" + ref(n.b) + " != 0.0) {\n" : "  {\n");
    os_ << "    double in[" << std::max<size_t>(1, args.size()) << "] = {";
    for (size_t i = 0; i < args.size(); ++i)
      os_ << (i ? ", " : "") << ref(args[i]);
    if (args.empty())
      os_ << "0.0";
    os_ << "};\n    double out[" << std::max(1u, x.numOutputs) << "];\n"
        << "    " << x.symbol << "(in, out);\n"
        << "    " << v << " = out[" << uint32_t(n.value) << "];\n  }\n";
    if (!n.mayFail)
      return;
    std::string e = "(" + v + " != " + v + ")";
    for (unsigned i = 0; i < numOperands(n.op); ++i)
      if (fn_.nodes[n.operand(i)].mayFail)
        e += " | " + err(n.operand(i));
    os_ << "  const int e" << k << " = " << e << ";\n";
  }

  std::ostream &os_;
  const PlanFunction &fn_;
  const PlanChunk &chunk_;
  std::string sym_;
  bool inLoop_;
};

const char *kChunkParams =
    "(double t, const double *restrict y, const double *restrict yp, "
    "const double *restrict p, double cj, double *restrict out0, "
    "double *restrict out1, double *restrict tmp)";

std::string exportedParams(FnSig sig) {
  if (sig == FnSig::State)
    return "(double t, const double *restrict y, const double *restrict p, "
           "double *restrict out0)";
  std::string s = "(double t, const double *restrict y, const double "
                  "*restrict yp, const double *restrict p, ";
  if (sig == FnSig::Jacobian)
    s += "double cj, ";
  s += "double *restrict out0";
  if (sig == FnSig::InitJacobian)
    s += ", double *restrict out1";
  return s + ")";
}

template <typename T, typename F>
void printArray(std::ostream &os, const std::string &type,
                const std::string &name, const std::vector<T> &values,
                F format, const char *storage = "static const ");

/// The non-affine index columns of a loop as static tables, for
/// printLoopHeader.
void printColumnTables(std::ostream &os, const std::string &sym,
                       const PlanLoop &loop) {
  for (size_t c = 0; c < loop.columns.size(); ++c)
    if (!loop.columns[c].affine())
      printArray(os, "int", sym + "_c" + std::to_string(c),
                 loop.columns[c].table,
                 [](int32_t v) { return std::to_string(v); });
}

/// `for (i ...) {` and the iteration's index columns c0, c1, ...
void printLoopHeader(std::ostream &os, const std::string &sym,
                     const PlanLoop &loop) {
  os << "  for (long i = 0; i < " << loop.count << "; ++i) {\n";
  for (size_t c = 0; c < loop.columns.size(); ++c) {
    const IndexColumn &col = loop.columns[c];
    os << "  const long c" << c << " = ";
    if (col.affine())
      os << col.base << " + " << col.stride << " * i;\n";
    else
      os << sym << "_c" << c << "[i];\n";
    os << "  (void)c" << c << ";\n";
  }
}

/// A loop (PlanLoop) as a static function of the chunk signature.
void printLoop(std::ostream &os, const std::string &sym, const PlanLoop &loop,
               const std::string &fnSym) {
  printColumnTables(os, sym, loop);
  os << "static int " << sym << kChunkParams << " {\n"
     << "  int rc = 0;\n"
     << "  (void)t; (void)y; (void)yp; (void)p; (void)cj; (void)out0; "
        "(void)out1; (void)tmp;\n";
  printLoopHeader(os, sym, loop);
  ChunkPrinter(os, loop.body, loop.body.chunks[0], fnSym, true).print();
  os << "  }\n  return rc;\n}\n\n";
}

/// A reduction as `static double <sym>(t, y, yp, p, cj, acc, int *err)`.
void printReduction(std::ostream &os, const std::string &sym,
                    const PlanLoop &r, const std::string &fnSym) {
  printColumnTables(os, sym, r);
  os << "static double " << sym
     << "(double t, const double *restrict y, const double *restrict yp, "
        "const double *restrict p, double cj, double acc, int *err) {\n"
     << "  int failed = 0;\n"
     << "  (void)t; (void)y; (void)yp; (void)p; (void)cj;\n";
  printLoopHeader(os, sym, r);
  ChunkPrinter body(os, r.body, r.body.chunks[0], fnSym, true);
  body.print();
  uint32_t root = r.body.nodes.size() - 1;
  os << "  acc = acc " << (r.subtract ? "-" : "+") << " "
     << body.valueOf(root) << ";\n"
     << "  failed |= " << body.errorOf(root) << ";\n"
     << "  }\n  if (err) *err |= failed;\n  return acc;\n}\n\n";
}

void printFunction(std::ostream &os, const CodePlan &plan,
                   const PlanFunction &fn) {
  std::string sym = functionSymbol(plan, fn);
  bool single = fn.chunks.size() == 1 && fn.loops.empty();
  // The straight-line chunks, then the loops: called in order while no
  // error has been returned (as the LLVM emitter does).
  std::vector<std::string> parts;
  for (size_t r = 0; r < fn.reductions.size(); ++r)
    printReduction(os, sym + "_reduce" + std::to_string(r), fn.reductions[r],
                   sym);
  if (!single) {
    for (size_t c = 0; !fn.stores.empty() && c < fn.chunks.size(); ++c) {
      parts.push_back(sym + "_chunk" + std::to_string(c));
      os << "static int " << parts.back() << kChunkParams << " {\n"
         << "  int rc = 0;\n"
         << "  (void)t; (void)y; (void)yp; (void)p; (void)cj; (void)out0; "
            "(void)out1; (void)tmp;\n";
      ChunkPrinter(os, fn, fn.chunks[c], sym).print();
      os << "  return rc;\n}\n\n";
    }
    for (size_t l = 0; l < fn.loops.size(); ++l) {
      parts.push_back(sym + "_loop" + std::to_string(l));
      printLoop(os, parts.back(), fn.loops[l], sym);
    }
  }
  os << "int " << sym << exportedParams(fn.sig) << " {\n";
  // A function over (t, y) hands its chunks y as the never-read yp.
  if (fn.sig == FnSig::State)
    os << "  const double *const yp = y;\n";
  if (fn.sig != FnSig::Jacobian)
    os << "  const double cj = 0.0;\n";
  if (fn.sig != FnSig::InitJacobian)
    os << "  double *const out1 = 0;\n";
  os << "  int rc = 0;\n"
     << "  (void)t; (void)y; (void)yp; (void)p; (void)cj; (void)out0; "
        "(void)out1;\n";
  for (unsigned i = 0; i < 2; ++i)
    if (fn.zeroFill[i])
      os << "  memset(out" << i << ", 0, " << fn.zeroFill[i]
         << " * sizeof(double));\n";
  if (single) {
    os << "  {\n";
    ChunkPrinter(os, fn, fn.chunks[0], sym).print();
    os << "  }\n  return rc;\n}\n\n";
    return;
  }
  bool heap = fn.numSpillSlots > 8192;
  if (heap)
    os << "  double *tmp = (double *)malloc(" << fn.numSpillSlots
       << " * sizeof(double));\n  if (!tmp) return -1;\n";
  else
    os << "  double tmp[" << std::max(1u, fn.numSpillSlots) << "];\n";
  for (size_t c = 0; c < parts.size(); ++c)
    os << "  " << (c ? "if (!rc) " : "") << "rc = " << parts[c]
       << "(t, y, yp, p, cj, out0, out1, tmp);\n";
  if (heap)
    os << "  free(tmp);\n";
  os << "  return rc;\n}\n\n";
}

/// The shared objects of the external functions the plan calls, each
/// once, by path (the program loads them from where ldaec built them), in
/// the order the linker needs: an object before those it uses, the reverse
/// of the load order (ExternalLibraries.h). Each function's objects come in
/// load order, so the first occurrences of all of them are in load order.
std::string linkedObjects(const std::vector<const CodePlan *> &plans) {
  std::vector<std::string> loadOrder;
  auto add = [&](const PlanExternal &x) {
    for (const std::string &o : x.objects)
      if (std::find(loadOrder.begin(), loadOrder.end(), o) == loadOrder.end())
        loadOrder.push_back(o);
  };
  for (const CodePlan *plan : plans) {
    for (const CodePlan::Replay &r : plan->replays)
      add(r.external);
    for (const PlanExternal &x : plan->externals)
      add(x);
  }
  std::string list;
  for (auto it = loadOrder.rbegin(); it != loadOrder.rend(); ++it)
    list += " " + *it;
  return list;
}

/// The command that builds the program of `--emit c --main` from
/// `<sym>.c`: the runtime library of the ldaec that wrote it.
std::string mainCompileCommand(const std::vector<const CodePlan *> &plans) {
  const std::string &sym = plans.back()->symbolName;
  std::string lib = LDAE_RUNTIME_LIBDIR;
  return "cc " LDAE_MAIN_CFLAGS " " + sym + ".c" + linkedObjects(plans) +
         " -L" + lib + " -lldaert -Wl,-rpath," + lib + " -lm -o " + sym;
}

/// The external functions' declarations (their wrappers' one signature).
void printExternalDeclarations(std::ostream &os, const CodePlan &plan) {
  std::vector<std::string> seen;
  auto declare = [&](const PlanExternal &x) {
    if (std::find(seen.begin(), seen.end(), x.symbol) == seen.end()) {
      seen.push_back(x.symbol);
      os << "void " << x.symbol << "(const double *in, double *out);\n";
    }
  };
  for (const CodePlan::Replay &r : plan.replays)
    declare(r.external);
  for (const PlanExternal &x : plan.externals)
    declare(x);
  if (!seen.empty())
    os << "\n";
}

/// `int <sym>_make_objects(void)`: makes again the impure calls made when
/// compiling (CodePlan::replays, for their effects on the C code's state:
/// a random generator's seed), then calls the constructors of the model's
/// external objects (CodePlan::objects) over the parameters and stores the
/// handles among them; 0, or nonzero when a call failed (its message on
/// stderr). A handle is a pointer of the process that made it, so the
/// compiled values are replaced before the model is used. The models of
/// the modes compiled ahead (`modes`, their symbols) get the same handles:
/// a table keeps its state across a change of mode.
void printMakeObjects(std::ostream &os, const CodePlan &plan,
                      const std::vector<std::string> &modes) {
  const std::string &s = plan.symbolName;
  const bool objects = plan.objects >= 0;
  if (objects)
    printArray(os, "int", s + "_object_params", plan.objectParams,
               [](int v) { return std::to_string(v); });
  os << "const char *ldae_modelica_take_error(void);\n\n"
     << "int " << s << "_make_objects(void) {\n";
  for (const CodePlan::Replay &r : plan.replays) {
    os << "  {\n    double in[" << std::max<size_t>(1, r.inputs.size())
       << "] = {";
    for (size_t k = 0; k < r.inputs.size(); ++k)
      os << (k ? ", " : "") << number(r.inputs[k]);
    if (r.inputs.empty())
      os << "0.0";
    os << "};\n    double out[" << std::max(1u, r.external.numOutputs)
       << "];\n    const char *why;\n"
       << "    " << r.external.symbol << "(in, out);\n"
       << "    if ((why = ldae_modelica_take_error()) != 0) {\n"
       << "      fprintf(stderr, \"error: a call made when compiling failed "
          "when made again: %s\\n\", why);\n"
       << "      return 1;\n    }\n  }\n";
  }
  if (objects) {
    os << "  double made[" << plan.objectParams.size() << "];\n"
       << "  int j, rc = "
       << functionSymbol(plan, plan.functions[plan.objects]) << "(0.0, " << s
       << "_start_y, " << s << "_start_yp, " << s << "_param_values, made);\n"
       << "  if (rc != 0) {\n"
       << "    const char *why = ldae_modelica_take_error();\n"
       << "    fprintf(stderr, \"error: the external object '%s' could not be "
          "made%s%s\\n\",\n"
       << "            " << s << "_param_names[" << s
       << "_object_params[rc > 0 ? rc - 1 : 0]], why ? \": \" : \"\", why ? "
          "why : \"\");\n"
       << "    return rc > 0 ? rc : 1;\n  }\n"
       << "  for (j = 0; j < " << plan.objectParams.size() << "; ++j) {\n"
       << "    " << s << "_param_values[" << s
       << "_object_params[j]] = made[j];\n";
    for (const std::string &m : modes)
      os << "    " << m << "_param_values[" << s
         << "_object_params[j]] = made[j];\n";
    os << "  }\n";
  }
  os << "  return 0;\n}\n\n";
}

template <typename T, typename F>
void printArray(std::ostream &os, const std::string &type,
                const std::string &name, const std::vector<T> &values,
                F format, const char *storage) {
  os << storage << type << " " << name << "[] = {";
  if (values.empty())
    os << "0"; // C has no empty arrays
  for (size_t i = 0; i < values.size(); ++i)
    os << (i ? "," : "") << (i % 8 == 0 ? "\n  " : " ") << format(values[i]);
  os << "\n};\n";
}

/// The tables of the events block (ABI 6) before the model struct; returns
/// the block's initializers, in the order of ldae_model. A table whose
/// count is 0 is NULL, as ModelTables makes it.
std::string printEventTables(std::ostream &os, const CodePlan &plan) {
  const EventPlan &ev = plan.events;
  const std::string &s = plan.symbolName;
  std::ostringstream init;
  auto table = [&](const std::string &type, const std::string &field,
                   const auto &values, auto format) {
    if (values.empty())
      return std::string("0");
    printArray(os, type, s + "_" + field, values, format);
    return s + "_" + field;
  };
  auto str = [](const std::string &v) { return quote(v); };
  auto dbl = [](double v) { return number(v); };
  auto integer = [](int v) { return std::to_string(v); };
  auto fnRef = [&](int i) {
    return i < 0 ? std::string("0") : functionSymbol(plan, plan.functions[i]);
  };
  // Per state set rows: a table of pointers to one array per row.
  auto rows = [&](const std::string &field,
                  const std::vector<std::vector<int>> &t) {
    if (t.empty())
      return std::string("0");
    std::vector<std::string> names;
    for (size_t i = 0; i < t.size(); ++i) {
      names.push_back(s + "_" + field + std::to_string(i));
      printArray(os, "int", names.back(), t[i], integer);
    }
    printArray(os, "int *const", s + "_" + field, names,
               [](const std::string &v) { return v; });
    return s + "_" + field;
  };
  init << "  " << ev.numDiscrete() << ", "
       << table("char *const", "discrete_names", ev.discreteNames, str) << ", "
       << table("double", "discrete_start", ev.discreteStart, dbl) << ", "
       << table("int", "discrete_kind", ev.discreteKind, integer) << ", "
       << table("int", "root_relation", ev.rootRelation, integer) << ",\n  "
       << ev.reinitTarget.size() << ", "
       << table("int", "reinit_target", ev.reinitTarget, integer) << ", "
       << ev.terminateMessage.size() << ", "
       << table("char *const", "terminate_message", ev.terminateMessage, str)
       << ", " << fnRef(ev.update) << ",\n  " << ev.thresholdRelation.size()
       << ", "
       << table("int", "threshold_relation", ev.thresholdRelation, integer)
       << ", " << ev.sampleDiscrete.size() << ", "
       << table("int", "sample_discrete", ev.sampleDiscrete, integer) << ", "
       << fnRef(ev.timeEvents) << ",\n  " << ev.assertMessage.size() << ", "
       << table("char *const", "assert_message", ev.assertMessage, str) << ", "
       << table("int", "assert_level", ev.assertLevel, integer) << ", "
       << table("char *const", "assert_origin", ev.assertOrigin, str) << ", "
       << fnRef(ev.asserts) << ", "
       << table("int", "assert_value_begin", ev.assertValueBegin, integer)
       << ",\n  " << ev.modeDiscrete.size() << ", "
       << table("int", "mode_discrete", ev.modeDiscrete, integer) << ", "
       << table("double", "mode_values", ev.modeValues, dbl) << ",\n  "
       << rows("dummy_of", ev.dummyOf) << ", "
       << rows("original_row", ev.originalRow) << "\n";
  return init.str();
}

/// The tables of the results block (ABI 7) before the model struct;
/// returns the block's initializers, designated like the next block's.
std::string printResultTables(std::ostream &os, const CodePlan &plan) {
  const std::string &s = plan.symbolName;
  auto str = [](const std::string &v) { return quote(v); };
  auto integer = [](int v) { return std::to_string(v); };
  auto table = [&](const std::string &type, const std::string &field,
                   const auto &values, auto format) {
    printArray(os, type, s + "_" + field, values, format);
    return "." + field + " = " + s + "_" + field;
  };
  std::ostringstream init;
  init << "  " << table("char *const", "output_unit", plan.outputUnit, str)
       << ",\n  "
       << table("char *const", "output_description", plan.outputDescription,
                str)
       << ",\n  " << table("int", "output_alias", plan.outputAlias, integer)
       << ",\n  " << table("char *const", "param_unit", plan.paramUnit, str)
       << ",\n  "
       << table("char *const", "param_description", plan.paramDescription,
                str)
       << "\n";
  return init.str();
}

/// The tables of the run-time parameters block (ABI 7) before the model
/// struct; returns the block's initializers, designated so the blocks
/// before it may grow without moving them.
std::string printBindingTables(std::ostream &os, const CodePlan &plan) {
  const std::string &s = plan.symbolName;
  auto integer = [](int v) { return std::to_string(v); };
  auto table = [&](const std::string &field, const std::vector<int> &values) {
    if (values.empty())
      return std::string("0");
    printArray(os, "int", s + "_" + field, values, integer);
    return s + "_" + field;
  };
  bool anyStructural =
      std::any_of(plan.structuralParams.begin(), plan.structuralParams.end(),
                  [](int s) { return s != 0; });
  std::ostringstream init;
  init << "  .bind = "
       << (plan.bind < 0 ? std::string("0")
                         : functionSymbol(plan, plan.functions[plan.bind]))
       << ",\n  .n_bound_params = " << plan.boundParams.size()
       << ", .bound_params = " << table("bound_params", plan.boundParams)
       << ",\n  .n_bound_starts = " << plan.boundStarts.size()
       << ", .bound_starts = " << table("bound_starts", plan.boundStarts)
       << ",\n  .bind_passes = " << plan.bindPasses
       << ", .param_structural = "
       << (anyStructural ? table("param_structural", plan.structuralParams)
                         : std::string("0"))
       << "\n";
  return init.str();
}

/// Everything of one model: its functions, its tables and its
/// `const ldae_model ldae_model_<symbol>`, whose modes block (ABI 12) is
/// `modeBlock`. `modes`: the symbols of the models of the modes compiled
/// ahead, when this is the model that makes the external objects.
void printModel(std::ostream &os, const CodePlan &plan,
                const std::string &modeBlock, bool makesObjects,
                const std::vector<std::string> &modes) {
  const std::string &s = plan.symbolName;
  const bool objects = plan.objects >= 0;
  printExternalDeclarations(os, plan);
  for (const PlanFunction &fn : plan.functions)
    printFunction(os, plan, fn);

  auto str = [](const std::string &v) { return quote(v); };
  auto dbl = [](double v) { return number(v); };
  auto integer = [](int v) { return std::to_string(v); };
  printArray(os, "char *const", s + "_var_names", plan.varNames, str);
  printArray(os, "double", s + "_start_y", plan.startY, dbl);
  printArray(os, "double", s + "_start_yp", plan.startYp, dbl);
  printArray(os, "double", s + "_nominal", plan.nominal, dbl);
  printArray(os, "int", s + "_fixed", plan.fixed, integer);
  printArray(os, "char *const", s + "_param_names", plan.paramNames, str);
  // The handles of external objects are stored at run time.
  printArray(os, "double", s + "_param_values", plan.paramValues, dbl,
             objects ? "static " : "static const ");
  if ((objects || !plan.replays.empty()) && makesObjects)
    printMakeObjects(os, plan, modes);
  printArray(os, "char *const", s + "_output_names", plan.outputNames, str);
  if (!plan.residualOrigin.empty())
    printArray(os, "char *const", s + "_residual_origin", plan.residualOrigin,
               str);
  if (!plan.outputOrigin.empty())
    printArray(os, "char *const", s + "_output_origin", plan.outputOrigin,
               str);
  auto fnRef = [&](int i) {
    return i < 0 ? std::string("0") : functionSymbol(plan, plan.functions[i]);
  };
  for (size_t i = 0; i < plan.stateSets.size(); ++i) {
    const StateSetPlan &sp = plan.stateSets[i];
    std::string p = s + "_set" + std::to_string(i);
    printArray(os, "int", p + "_is_differential", sp.isDifferential, integer);
    printArray(os, "int", p + "_colptr", sp.colptr, integer);
    printArray(os, "int", p + "_rowind", sp.rowind, integer);
  }
  printArray(os, "int", s + "_init_colptr", plan.initColptr, integer);
  printArray(os, "int", s + "_init_rowind", plan.initRowind, integer);
  const bool tested = !plan.testedNominal.empty();
  if (tested) {
    printArray(os, "double", s + "_tested_nominal", plan.testedNominal, dbl);
    printArray(os, "int", s + "_tested_colptr", plan.testedColptr, integer);
    printArray(os, "int", s + "_tested_rowind", plan.testedRowind, integer);
  }
  const std::string events = printEventTables(os, plan);
  const std::string results = printResultTables(os, plan);
  const std::string bindings = printBindingTables(os, plan);
  os << "static const ldae_state_set " << s << "_state_sets[] = {\n";
  for (size_t i = 0; i < plan.stateSets.size(); ++i) {
    const StateSetPlan &sp = plan.stateSets[i];
    std::string p = s + "_set" + std::to_string(i);
    os << "  {" << p << "_is_differential, " << fnRef(sp.residual) << ", "
       << fnRef(sp.jacobianDense) << ", " << fnRef(sp.jacobianCsc) << ", "
       << sp.rowind.size() << ", " << p << "_colptr, " << p << "_rowind, "
       << sp.pivotSize << ", " << fnRef(sp.pivot) << ", "
       << quote(sp.description) << "},\n";
  }
  os << "};\n\n";
  for (size_t i = 0; i < plan.dynamicSets.size(); ++i) {
    const DynamicSetPlan &dp = plan.dynamicSets[i];
    std::string p = s + "_dynamic" + std::to_string(i);
    printArray(os, "double", p + "_start", dp.start, dbl);
    printArray(os, "int", p + "_state_slots", dp.stateSlots, integer);
    printArray(os, "char *const", p + "_names", dp.names, str);
  }
  if (!plan.dynamicSets.empty()) {
    os << "static const ldae_dynamic_set " << s << "_dynamic_sets[] = {\n";
    for (size_t i = 0; i < plan.dynamicSets.size(); ++i) {
      const DynamicSetPlan &dp = plan.dynamicSets[i];
      std::string p = s + "_dynamic" + std::to_string(i);
      os << "  {" << dp.rows << ", " << dp.forced << ", " << dp.candidates
         << ", " << fnRef(dp.jacobian) << ", " << fnRef(dp.values) << ", "
         << dp.param << ", " << p << "_start, " << p << "_state_slots, " << p
         << "_names},\n";
    }
    os << "};\n\n";
  }
  const std::string dynamic = plan.dynamicSets.empty()
                                  ? std::string("0, 0, 0")
                                  : std::to_string(plan.dynamicSets.size()) +
                                        ", " + s + "_dynamic_sets, " +
                                        std::to_string(plan.selectionCount);
  os << "const ldae_model ldae_model_" << s << " = {\n"
     << "  LDAE_ABI_VERSION, " << quote(plan.name) << ",\n"
     << "  " << plan.n << ", " << s << "_var_names, " << s << "_start_y, " << s
     << "_start_yp, " << s << "_nominal, " << s << "_fixed,\n"
     << "  " << plan.paramValues.size() << ", " << s << "_param_names, " << s
     << "_param_values,\n"
     << "  " << plan.stateSets.size() << ", " << s << "_state_sets,\n"
     << "  " << plan.nInit << ", " << fnRef(plan.initResidual) << ", "
     << fnRef(plan.initJacobian) << ",\n"
     << "  " << plan.nRoots << ", " << fnRef(plan.roots) << ",\n"
     << "  " << plan.nOutputs << ", " << s << "_output_names, "
     << fnRef(plan.outputs) << ",\n"
     << "  " << plan.nDrift << ", " << fnRef(plan.drift) << ",\n"
     << "  " << plan.nOde << ", " << plan.nConstraints << ", 0, "
     << fnRef(plan.constraints) << ", " << fnRef(plan.constraintJacobian)
     << ",\n"
     << "  " << (plan.residualOrigin.empty() ? "0" : s + "_residual_origin")
     << ",\n"
     << "  " << number(plan.startTime) << ", " << number(plan.stopTime) << ", "
     << number(plan.tolerance) << ", " << number(plan.interval) << ",\n"
     << "  " << plan.initRowind.size() << ", " << s << "_init_colptr, " << s
     << "_init_rowind, " << fnRef(plan.initJacobianCsc) << ",\n"
     << "  " << (plan.outputOrigin.empty() ? "0" : s + "_output_origin")
     << ",\n  " << (plan.explicitOde ? 1 : 0) << ", "
     << (plan.algebraicErrorTest ? 1 : 0) << ", "
     << (plan.projectConstraints ? 1 : 0) << ",\n  "
     << plan.testedNominal.size() << ", "
     << (tested ? s + "_tested_nominal" : "0") << ", " << fnRef(plan.tested)
     << ", " << plan.testedRowind.size() << ", "
     << (tested ? s + "_tested_colptr" : "0") << ", "
     << (tested ? s + "_tested_rowind" : "0") << ", "
     << fnRef(plan.testedJacobianCsc) << ",\n"
     << events << ",\n"
     << results << ",\n"
     << bindings << ",\n  " << dynamic << ",\n  " << plan.nWritten << ", "
     << fnRef(plan.writtenResidual) << ", " << fnRef(plan.writtenJacobian)
     << ",\n  " << modeBlock << "};\n\n";
}

} // namespace

std::string printC(const CodePlan &plan, bool withMain,
                   const std::vector<ModePlan> &modes) {
  std::ostringstream os;
  const std::string &s = plan.symbolName;
  std::vector<const CodePlan *> plans;
  for (const ModePlan &m : modes)
    plans.push_back(&m.plan);
  plans.push_back(&plan);
  os << "/* Generated by ldaec from model " << quote(plan.name)
     << ": the C ABI of ldae/model.h";
  // make_objects: external objects to make, or compile-time calls to make
  // again.
  const bool objects = plan.objects >= 0 || !plan.replays.empty();
  if (withMain)
    os << ",\n   and a main that runs it with the ldaec runtime (ldae/run.h, "
          "libldaert).\n   Compile (docs/embedding-c.md):\n     "
       << mainCompileCommand(plans) << "\n   ./" << s
       << " --help lists its options. */\n";
  else
    os << ".\n   Compile: cc -O2 -c " << s << ".c"
       << (linkedObjects(plans).empty()
               ? ""
               : " and link the program with" + linkedObjects(plans) +
                     (objects ? "; call " + s +
                                    "_make_objects() once before using the "
                                    "model"
                              : ""))
       << " (see docs/embedding-c.md). */\n";
  os << "#include <math.h>\n" << (objects ? "#include <stdio.h>\n" : "")
     << "#include <stdlib.h>\n#include <string.h>\n\n"
     << kModelHeaderText << "\n";
  if (withMain)
    os << kRunHeaderText << "\n";
  // The modes compiled ahead (variable structure), then their table, then
  // the model of the start, which holds it.
  std::vector<std::string> modeSymbols;
  std::vector<double> modeValues;
  for (const ModePlan &m : modes) {
    printModel(os, m.plan, "0, 0, 0", false, {});
    modeSymbols.push_back(m.plan.symbolName);
    modeValues.insert(modeValues.end(), m.values.begin(), m.values.end());
  }
  std::string modeBlock = "0, 0, 0";
  if (!modes.empty()) {
    printArray(os, "double", s + "_mode_model_values", modeValues,
               [](double v) { return number(v); });
    printArray(os, "ldae_model *const", s + "_mode_models", modeSymbols,
               [](const std::string &m) { return "&ldae_model_" + m; });
    modeBlock = std::to_string(modes.size()) + ", " + s +
                "_mode_model_values, " + s + "_mode_models";
  }
  printModel(os, plan, modeBlock, true, modeSymbols);
  os << "const ldae_model *ldae_get_model(void) { return &ldae_model_" << s
     << "; }\n";
  if (withMain)
    os << "\nint main(int argc, char **argv) {\n"
       << (objects ? "  if (" + s + "_make_objects() != 0)\n    return 3;\n"
                   : "")
       << "  return ldae_main(&ldae_model_" << s << ", argc, argv);\n}\n";
  return os.str();
}

} // namespace ldae::codegen
