// Modelica.Utilities.Files.loadResource(uri) (MLS 13.5): the tool resolves
// a URI to a file name, so ldaec answers it in place of ModelicaServices'
// default (which takes local names only). `modelica://Pkg.Sub/rest` is
// `rest` under the directory of class Pkg.Sub as loaded (its package.mo's
// directory, or the directory of its own file); `file:///path` is /path;
// anything else is a file name, returned as written. The text is known
// when compiling, like every String (docs/language.md).
#include "frontend/Flattener.h"

#include <filesystem>

namespace ldae::frontend {

bool isLoadResource(const ast::ClassDef &fn) {
  std::string q = fn.qualifiedName();
  return q == "Modelica.Utilities.Files.loadResource" ||
         q == "ModelicaServices.ExternalReferences.loadResource";
}

std::optional<Value> Flattener::lowerLoadResource(const ast::Expr &call,
                                                  const Scope &scope,
                                                  Env *env) {
  SourceRange where{call.loc, call.length};
  if (call.args.size() != 1 || !call.args[0].name.empty() &&
                                   call.args[0].name != "uri") {
    report(DiagId::ErrCallArgCount,
           where, {"loadResource", "1", std::to_string(call.args.size())});
    return std::nullopt;
  }
  const ast::Expr &arg = *call.args[0].value;
  std::optional<Value> uri = lower(arg, scope, env);
  if (!uri)
    return std::nullopt;
  if (!uri->isString) {
    report(DiagId::ErrArgumentType, SourceRange{arg.loc, arg.length},
           {"uri", "loadResource", "a string", "a number"});
    return std::nullopt;
  }
  const std::string modelicaScheme = "modelica://", fileScheme = "file://";
  const std::string &text = uri->str;
  if (text.compare(0, fileScheme.size(), fileScheme) == 0)
    return Value::string(text.substr(fileScheme.size()));
  if (text.compare(0, modelicaScheme.size(), modelicaScheme) != 0)
    return Value::string(text);
  std::string rest = text.substr(modelicaScheme.size());
  std::string className = rest.substr(0, rest.find('/'));
  std::string path =
      rest.size() > className.size() ? rest.substr(className.size() + 1) : "";
  ast::Name name;
  name.global = true;
  name.loc = arg.loc;
  for (size_t start = 0;;) {
    size_t dot = className.find('.', start);
    name.parts.push_back(className.substr(start, dot - start));
    if (dot == std::string::npos)
      break;
    start = dot + 1;
  }
  const ast::ClassDef *cls =
      classes_.resolveClass(name, nullptr, call.loc.file, /*report=*/false);
  std::filesystem::path file =
      cls ? std::filesystem::path(diags_.sources().path(cls->file)) : "";
  // The class must be stored as its own file: nested classes have no
  // directory of their own.
  bool ownFile = cls && (file.filename() == "package.mo" ||
                         file.stem().string() == cls->name) &&
                 (!cls->parent || cls->parent->file != cls->file);
  if (!ownFile) {
    report(DiagId::ErrUnsupported, SourceRange{arg.loc, arg.length},
           {"the resource \"" + text + "\": " +
            (cls ? "class '" + className + "' is not stored in a file of its own"
                 : "no class '" + className + "' is loaded")});
    return std::nullopt;
  }
  return Value::string((file.parent_path() / path).lexically_normal().string());
}

} // namespace ldae::frontend
