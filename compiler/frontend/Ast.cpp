// Small helpers of the AST: names as the user wrote them.
#include "frontend/Ast.h"

namespace ldae::frontend::ast {

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
