// Small helpers of the AST: names as the user wrote them.
#include "frontend/Ast.h"

namespace ldae::frontend::ast {

namespace {
/// Moves the subexpressions of `e` to `out`, leaving `e` without children.
void detachChildren(Expr &e, std::vector<ExprPtr> &out) {
  for (ExprPtr &op : e.ops)
    out.push_back(std::move(op));
  for (RefPart &p : e.parts)
    for (ExprPtr &s : p.subscripts)
      out.push_back(std::move(s));
  for (Arg &a : e.args)
    out.push_back(std::move(a.value));
  for (ForIndex &it : e.iterators)
    out.push_back(std::move(it.range));
  for (auto &row : e.rows)
    for (ExprPtr &x : row)
      out.push_back(std::move(x));
}
} // namespace

Expr::~Expr() {
  std::vector<ExprPtr> pending;
  detachChildren(*this, pending);
  while (!pending.empty()) {
    ExprPtr e = std::move(pending.back());
    pending.pop_back();
    if (e)
      detachChildren(*e, pending); // `e` then dies without recursing
  }
}

Name Expr::calleeName() const {
  Name fname;
  fname.global = global;
  for (const auto &p : parts)
    fname.parts.push_back(p.name);
  fname.loc = loc;
  fname.length = static_cast<uint32_t>(text.size());
  return fname;
}

std::string Expr::refName() const {
  std::string s = global ? "." : "";
  for (size_t i = 0; i < parts.size(); ++i) {
    if (i)
      s += '.';
    s += parts[i].name;
  }
  return s;
}

std::string Name::str() const {
  std::string s = global ? "." : "";
  for (size_t i = 0; i < parts.size(); ++i) {
    if (i)
      s += '.';
    s += parts[i];
  }
  return s;
}

const char *classKindName(ClassKind k) {
  switch (k) {
  case ClassKind::Class:
    return "class";
  case ClassKind::Model:
    return "model";
  case ClassKind::Record:
    return "record";
  case ClassKind::Block:
    return "block";
  case ClassKind::Connector:
    return "connector";
  case ClassKind::Type:
    return "type";
  case ClassKind::Package:
    return "package";
  case ClassKind::Function:
    return "function";
  case ClassKind::Operator:
    return "operator";
  }
  return "class";
}

std::string ClassDef::qualifiedName() const {
  return parent ? parent->qualifiedName() + "." + name : name;
}

} // namespace ldae::frontend::ast
