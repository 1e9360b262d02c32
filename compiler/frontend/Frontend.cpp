// compileFile: read, parse, pick the model, flatten. The one entry point
// the driver calls; everything else of the frontend is behind it.
#include "frontend/Frontend.h"
#include "frontend/ClassTable.h"
#include "frontend/Flattener.h"
#include "frontend/Parser.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace ldae::frontend {
namespace {

bool isModelKind(const ast::ClassDef &c) {
  return c.kind == ast::ClassKind::Model || c.kind == ast::ClassKind::Block ||
         c.kind == ast::ClassKind::Class;
}

/// The last non-partial model of the file: at the top level, else the last
/// one nested in packages.
const ast::ClassDef *lastModel(const std::vector<std::unique_ptr<ast::ClassDef>> &classes) {
  for (auto it = classes.rbegin(); it != classes.rend(); ++it)
    if (isModelKind(**it) && !(*it)->partial && !(*it)->isShort)
      return it->get();
  for (auto it = classes.rbegin(); it != classes.rend(); ++it)
    if ((*it)->kind == ast::ClassKind::Package)
      if (const ast::ClassDef *m = lastModel((*it)->classes))
        return m;
  return nullptr;
}

void modelNames(const std::vector<std::unique_ptr<ast::ClassDef>> &classes,
                std::vector<std::string> &out) {
  for (const auto &c : classes) {
    if (isModelKind(*c))
      out.push_back(c->qualifiedName());
    modelNames(c->classes, out);
  }
}

std::unique_ptr<ir::Model> compileFileId(uint32_t id, const FrontendOptions &opts,
                                         SourceManager &sources,
                                         DiagnosticEngine &diags) {
  std::unique_ptr<ast::StoredDefinition> def = parseFile(id, sources, diags);
  if (!def)
    return nullptr;
  ClassTable classes(sources, diags,
                     libraryPath(opts.libraryPaths, LDAE_STDLIB_DIR));
  const ast::StoredDefinition *main = def.get();
  classes.addFile(std::move(def));
  if (diags.hasErrors())
    return nullptr;

  const ast::ClassDef *cls = nullptr;
  if (!opts.modelName.empty()) {
    ast::Name name;
    size_t start = 0;
    while (true) {
      size_t dot = opts.modelName.find('.', start);
      name.parts.push_back(opts.modelName.substr(start, dot - start));
      if (dot == std::string::npos)
        break;
      start = dot + 1;
    }
    cls = classes.resolveClass(name, nullptr, id, /*report=*/false);
    if (!cls) {
      std::vector<std::string> names;
      modelNames(main->classes, names);
      std::string best = closestName(opts.modelName, names);
      if (best.empty())
        diags.report(DiagId::ErrModelNotFound, SourceLoc{},
                     {opts.modelName, sources.path(id)});
      else
        diags.report(DiagId::ErrModelNotFoundSuggest, SourceLoc{},
                     {opts.modelName, sources.path(id), best});
      return nullptr;
    }
  } else {
    cls = lastModel(main->classes);
    if (!cls) {
      // The file is the model's error: point into it (at its last class,
      // or its start when it has none).
      SourceRange where{SourceLoc{id, 1, 1}, 1};
      if (!main->classes.empty())
        where = SourceRange{main->classes.back()->loc,
                            main->classes.back()->length};
      diags.report(DiagId::ErrNoModel, where, {sources.path(id)});
      return nullptr;
    }
  }
  if (cls->isShort || cls->kind == ast::ClassKind::Package ||
      cls->kind == ast::ClassKind::Function ||
      cls->kind == ast::ClassKind::Type ||
      cls->kind == ast::ClassKind::Operator) {
    diags.report(DiagId::ErrNotAModel, SourceRange{cls->loc, cls->length},
                 {cls->name, ast::classKindName(cls->kind)});
    return nullptr;
  }
  if (cls->partial) {
    diags.report(DiagId::ErrPartialModel, SourceRange{cls->loc, cls->length},
                 {cls->name});
    return nullptr;
  }
  Flattener flattener(classes, diags, opts);
  std::unique_ptr<ir::Model> model = flattener.flatten(*cls);
  if (model && !checkDiscreteDerivatives(*model, diags))
    return nullptr;
  if (model)
    startFromInitialEquations(*model);
  return model;
}

} // namespace

ParamOverride parseParamOverride(const std::string &option) {
  ParamOverride o;
  size_t eq = option.find('=');
  if (eq == std::string::npos)
    return o;
  o.name = option.substr(0, eq);
  while (!o.name.empty() && o.name.back() == ' ')
    o.name.pop_back();
  o.text = option.substr(eq + 1);
  if (o.text == "true" || o.text == "false") {
    o.value = o.text == "true" ? 1.0 : 0.0;
    return o;
  }
  char *end = nullptr;
  errno = 0;
  double v = std::strtod(o.text.c_str(), &end);
  // An underflow (1e-400) is the nearest double, 0 or subnormal, as in
  // Python; an overflow is no number.
  if (!o.text.empty() && *end == '\0' && std::isfinite(v) &&
      !(errno == ERANGE && std::fabs(v) >= 1))
    o.value = v;
  return o;
}

void reportLoadError(DiagnosticEngine &diags, const std::string &path,
                     LoadError error) {
  switch (error) {
  case LoadError::NotRegularFile:
    diags.report(DiagId::ErrFileNotRegular, SourceLoc{}, {path});
    return;
  case LoadError::TooLarge:
    diags.report(DiagId::ErrFileTooLarge, SourceLoc{},
                 {path, std::to_string(SourceManager::kMaxFileBytes >> 20)});
    return;
  default:
    diags.report(DiagId::ErrCannotReadFile, SourceLoc{}, {path});
  }
}

std::unique_ptr<ir::Model> compileFile(const std::string &path,
                                       const FrontendOptions &opts,
                                       SourceManager &sources,
                                       DiagnosticEngine &diags) {
  LoadError error = LoadError::None;
  uint32_t id = sources.loadFile(path, &error);
  if (id == 0) {
    reportLoadError(diags, path, error);
    return nullptr;
  }
  return compileFileId(id, opts, sources, diags);
}

std::unique_ptr<ir::Model> compileSource(const std::string &path,
                                         std::string text,
                                         const FrontendOptions &opts,
                                         SourceManager &sources,
                                         DiagnosticEngine &diags) {
  uint32_t id = sources.addFile(path, std::move(text));
  return compileFileId(id, opts, sources, diags);
}

} // namespace ldae::frontend
