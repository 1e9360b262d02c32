// A record component with a value (MLS 7.2.4, 12.6): the value binds each
// field, as a modifier of the field written on the component would:
//   parameter FrictionParameters frictionParameters =
//       smpmData.frictionParameters;                      // another record
//   parameter FrictionParameters f = FrictionParameters(PRef = 10, ...);
// A reference to another record instance binds each field to that
// instance's field of the same name; a record constructor binds the fields
// its arguments name (positional ones in declaration order), the others
// keep their declarations' bindings. Final and protected fields keep their
// own bindings (they are computed from the others, not constructor inputs).
// Any other record-valued expression (a function's result, an if between
// records) is refused, at the value.
#include "frontend/Flattener.h"

namespace ldae::frontend {

namespace {

bool isBoundByValue(const InstNode &field) {
  return !field.decl->isFinal && !field.decl->isProtected &&
         field.decl->prefix.variability != ast::Variability::Constant;
}

} // namespace

ModPtr Flattener::fieldBinding(const Mod &whole, const std::string &field,
                               const ast::Expr *value, const Scope &scope) {
  auto m = std::make_shared<Mod>();
  m->value = value;
  m->text = field + " = " + whole.text;
  m->loc = whole.loc;
  m->length = whole.length;
  m->nameLoc = whole.nameLoc;
  m->nameLength = whole.nameLength;
  m->scope = scope;
  return m;
}

void Flattener::bindRecordValue(InstNode &node) {
  const Mod &whole = *node.mod;
  const ast::Expr &value = *whole.value;
  SourceRange where{whole.loc, whole.length};
  if (value.kind == ast::ExprKind::Ref) {
    std::optional<Selection> sel = selectComponents(value, whole.scope, nullptr);
    if (!sel)
      return;
    InstNode *source = sel->targets.size() == 1 && sel->targets[0].slot < 0
                           ? sel->targets[0].node
                           : nullptr;
    if (!source || source->isLeaf() || source->isArray() ||
        !sel->shape.empty()) {
      report(DiagId::ErrRecordValue, where,
             {node.path, node.typeName, value.refName()});
      return;
    }
    if (source == &node) {
      report(DiagId::ErrCyclicDefinition, where, {node.path});
      return;
    }
    for (auto &m : node.members) {
      if (!isBoundByValue(*m))
        continue;
      InstNode *from = source->findMember(m->name);
      if (!from) {
        report(DiagId::ErrRecordValueField, where,
               {node.path, value.refName(), source->typeName, m->name});
        continue;
      }
      auto ref = std::make_unique<ast::Expr>();
      ref->kind = ast::ExprKind::Ref;
      ref->loc = whole.loc;
      ref->length = whole.length;
      ref->parts.push_back(ast::RefPart{m->name, {}});
      m->mod = mergeMods(fieldBinding(whole, m->name, ref.get(),
                                      Scope{source, source->cls}),
                         m->mod);
      recordFieldRefs_.push_back(std::move(ref));
    }
    return;
  }
  if (value.kind == ast::ExprKind::Call) {
    ast::Name fname = value.calleeName();
    uint32_t file = whole.scope.cls ? whole.scope.cls->file : value.loc.file;
    const ast::ClassDef *cls = classes_.resolveClass(
        fname, value.global ? nullptr : whole.scope.cls, file);
    for (unsigned guard = 0; cls && cls->isShort && guard < 16; ++guard)
      cls = classes_.resolveClass(cls->shortBase, cls->parent, cls->file);
    if (cls && cls->kind == ast::ClassKind::Record) {
      // Positional arguments fill the fields in declaration order.
      std::vector<InstNode *> inputs;
      for (auto &m : node.members)
        if (isBoundByValue(*m))
          inputs.push_back(m.get());
      size_t position = 0;
      for (const ast::Arg &arg : value.args) {
        InstNode *field = nullptr;
        if (arg.name.empty()) {
          field = position < inputs.size() ? inputs[position] : nullptr;
          ++position;
        } else {
          InstNode *m = node.findMember(arg.name);
          field = m && isBoundByValue(*m) ? m : nullptr;
        }
        if (!field) {
          report(DiagId::ErrRecordConstructorArg,
                 SourceRange{arg.value->loc, arg.value->length},
                 {arg.name.empty() ? std::to_string(position) : arg.name,
                  cls->name, std::to_string(inputs.size())});
          continue;
        }
        field->mod = mergeMods(
            fieldBinding(whole, field->name, arg.value.get(), whole.scope),
            field->mod);
      }
      return;
    }
  }
  report(DiagId::ErrUnsupported, where,
         {"a value for a component of type '" + node.typeName +
          "' other than another record or a record constructor"});
}

} // namespace ldae::frontend
