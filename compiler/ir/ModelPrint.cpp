// Model::print: the whole flat model as lsd source (`--emit flat`), which
// the frontend reads back. Flat names that are not identifiers (`r1.v`,
// `m[2].s`) are quoted Modelica-style; only non-default attributes print.
#include "ir/Model.h"

#include "ir/MessageText.h"
#include "ir/Print.h"

#include <cmath>
#include <sstream>

namespace ldae::ir {

std::string printEquation(ExprContext &ctx, ExprRef residual,
                          const NameResolver *names) {
  auto isNegative = [](ExprRef t) {
    return (t->isConstant() && t->constant() < 0) ||
           (t->kind() == ExprKind::Mul && t->operand(0)->isConstant() &&
            t->operand(0)->constant() < 0);
  };
  std::vector<ExprRef> lhs, rhs;
  std::span<const ExprRef> terms(&residual, 1);
  if (residual->kind() == ExprKind::Add)
    terms = residual->operands();
  for (ExprRef t : terms) {
    if (isNegative(t) || t->isConstant())
      rhs.push_back(ctx.neg(t));
    else
      lhs.push_back(t);
  }
  return printLsd(ctx.add(lhs), names) + " = " + printLsd(ctx.add(rhs), names);
}

namespace {

std::string boolText(double v) { return v != 0 ? "true" : "false"; }

std::string variableDecl(const Variable &v) {
  std::string type = v.isBoolean    ? "Boolean"
                     : v.isInteger  ? "Integer"
                     : v.isDiscrete ? "discrete Real"
                                    : "Real";
  std::string prefix = v.isInput ? "input " : v.isOutput ? "output " : "";
  std::vector<std::string> attrs;
  if (v.hasStart)
    attrs.push_back("start = " +
                    (v.isBoolean ? boolText(v.start) : printNumber(v.start)));
  if (v.fixed)
    attrs.push_back("fixed = true");
  if (v.nominal != 1)
    attrs.push_back("nominal = " + printNumber(v.nominal));
  if (v.min != -INFINITY)
    attrs.push_back("min = " + printNumber(v.min));
  if (v.max != INFINITY)
    attrs.push_back("max = " + printNumber(v.max));
  if (!v.unit.empty())
    attrs.push_back("unit = " + printString(v.unit));
  if (v.stateSelect != StateSelect::Default)
    attrs.push_back(std::string("stateSelect = StateSelect.") +
                    stateSelectName(v.stateSelect));
  std::string decl = prefix + type + " " + printIdentifier(v.name);
  if (!attrs.empty()) {
    decl += '(';
    for (size_t i = 0; i < attrs.size(); ++i)
      decl += (i ? ", " : "") + attrs[i];
    decl += ')';
  }
  return decl + ";";
}

std::string parameterDecl(const Parameter &p) {
  std::string kind = p.isConstant ? "constant " : "parameter ";
  std::string type = p.isBoolean ? "Boolean" : p.isInteger ? "Integer" : "Real";
  std::string value = p.isBoolean ? boolText(p.value) : printNumber(p.value);
  return kind + type + " " + printIdentifier(p.name) + " = " + value + ";";
}

} // namespace

const std::pair<ExprRef, ExprRef> *Model::homotopyOf(ExprRef e) const {
  auto it = homotopies.find(e);
  return it == homotopies.end() ? nullptr : &it->second;
}

std::string Model::print() const {
  std::ostringstream os;
  std::string modelName = printIdentifier(name.empty() ? "Model" : name);
  os << "model " << modelName << "\n";
  for (const Parameter &p : parameters)
    // The blend parameter of homotopy() is the calls' own: they print as
    // written and make it again.
    if (homotopies.empty() || p.name != "homotopy.lambda")
      os << "  " << parameterDecl(p) << "\n";
  for (const Variable &v : variables)
    if (v.input == EventInput::None)
      os << "  " << variableDecl(v) << "\n";

  if (!equations.empty() || !whenClauses.empty() || !asserts.empty())
    os << "equation\n";
  for (const Equation &eq : equations)
    os << "  " << printEquation(ctx(), eq.residual, this) << ";\n";
  auto printAssert = [&](const Assert &a, const char *indent) {
    std::vector<std::string> values;
    for (ExprRef v : a.messageValues)
      values.push_back(printLsd(v, this));
    os << indent << "assert(" << printLsd(a.condition, this) << ", "
       << messageExpression(a.message, values)
       << (a.level ? ", AssertionLevel.warning" : "") << ");\n";
  };
  for (const Assert &a : asserts)
    printAssert(a, "  ");
  for (size_t i = 0; i < whenClauses.size(); ++i) {
    const WhenClause &w = whenClauses[i];
    os << (w.elsewhen ? "  elsewhen " : "  when ");
    if (w.elements.size() > 1) {
      // The vector as written: its elements fire one by one.
      os << "{";
      for (size_t k = 0; k < w.elements.size(); ++k)
        os << (k ? ", " : "") << printLsd(w.elements[k], this);
      os << "}";
    } else {
      os << printLsd(w.condition, this);
    }
    os << " then\n";
    for (const Reinit &r : w.reinits)
      os << "    reinit(" << printIdentifier(variableName(r.var)) << ", "
         << printLsd(r.value, this) << ");\n";
    for (size_t k = 0; k < w.equations.size(); ++k) {
      const Equation &eq = w.equations[k];
      if (k < w.targets.size())
        os << "    " << printLsd(w.targets[k], this) << " = "
           << printLsd(ctx().sub(w.targets[k], eq.residual), this) << ";\n";
      else
        os << "    " << printEquation(ctx(), eq.residual, this) << ";\n";
    }
    for (const Terminate &t : w.terminates)
      os << "    terminate(" << printString(t.message) << ");\n";
    for (const Assert &a : w.asserts)
      printAssert(a, "    ");
    if (i + 1 == whenClauses.size() || !whenClauses[i + 1].elsewhen)
      os << "  end when;\n";
  }
  if (!initialEquations.empty()) {
    os << "initial equation\n";
    for (const Equation &eq : initialEquations)
      os << "  " << printEquation(ctx(), eq.residual, this) << ";\n";
  }

  std::vector<std::string> exp;
  auto field = [&](const char *key, const std::optional<double> &v) {
    if (v)
      exp.push_back(std::string(key) + " = " + printNumber(*v));
  };
  field("StartTime", experiment.startTime);
  field("StopTime", experiment.stopTime);
  field("Tolerance", experiment.tolerance);
  field("Interval", experiment.interval);
  if (!exp.empty()) {
    os << "  annotation(experiment(";
    for (size_t i = 0; i < exp.size(); ++i)
      os << (i ? ", " : "") << exp[i];
    os << "));\n";
  }
  os << "end " << modelName << ";\n";
  return os.str();
}

} // namespace ldae::ir
