// External objects (MLS 12.9.7): a class that extends the predefined
// ExternalObject is an opaque handle, made by its `constructor` function
// and passed to external functions as `void *`. ldaec keeps the handle as
// a Real (the pointer's value, exact in a double's 53 bits for user-space
// addresses), a parameter set once from the constructor's call.
#pragma once

#include "frontend/Ast.h"

namespace ldae::frontend {

/// Whether `cls` extends ExternalObject.
inline bool isExternalObject(const ast::ClassDef &cls) {
  for (const ast::Extends &e : cls.extends)
    if (!e.base.global && e.base.parts.size() == 1 &&
        e.base.parts[0] == "ExternalObject")
      return true;
  return false;
}

/// Its constructor function, or null.
inline const ast::ClassDef *externalObjectConstructor(const ast::ClassDef &cls) {
  for (const auto &c : cls.classes)
    if (c->name == "constructor" && c->kind == ast::ClassKind::Function)
      return c.get();
  return nullptr;
}

} // namespace ldae::frontend
