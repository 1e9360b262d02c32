// Class lookup and library loading; see ClassTable.h.
#include "frontend/ClassTable.h"
#include "support/EditDistance.h"
#include "frontend/Frontend.h"
#include "frontend/Parser.h"

#include <algorithm>
#include <filesystem>

namespace ldae::frontend {

ClassTable::ClassTable(SourceManager &sources, DiagnosticEngine &diags,
                       std::vector<std::string> libraryPaths)
    : sources_(sources), diags_(diags), libraryPaths_(libraryPaths),
      loader_(sources, diags, std::move(libraryPaths),
              [this](std::unique_ptr<ast::StoredDefinition> def) {
                addFile(std::move(def));
              }) {}

void ClassTable::addFile(std::unique_ptr<ast::StoredDefinition> file) {
  files_.push_back(std::move(file));
}

const ast::StoredDefinition *ClassTable::file(uint32_t fileId) const {
  for (const auto &f : files_)
    if (f->file == fileId)
      return f.get();
  return nullptr;
}

const ast::ClassDef *ClassTable::topLevel(uint32_t fileId,
                                          const std::string &name) const {
  const ast::StoredDefinition *f = file(fileId);
  if (!f)
    return nullptr;
  // The last definition wins, as in a file read top to bottom.
  const ast::ClassDef *found = nullptr;
  for (const auto &c : f->classes)
    if (c->name == name)
      found = c.get();
  return found;
}

const ast::ClassDef *ClassTable::libraryPackage(const std::string &name) {
  auto it = library_.find(name);
  if (it != library_.end())
    return it->second;
  library_[name] = nullptr; // also guards against re-entry while parsing
  const ast::ClassDef *cls = loader_.topLevel(name);
  library_[name] = cls;
  return cls;
}

const ast::ClassDef *ClassTable::memberClass(const ast::ClassDef &cls,
                                             const std::string &name) {
  for (const auto &c : cls.classes)
    if (c->name == name)
      return c.get();
  // A directory package's child in a file of its own.
  if (const ast::ClassDef *c = loader_.child(cls, name))
    return c;
  if (importDepth_ > 32)
    return nullptr;
  ++importDepth_;
  const ast::ClassDef *found = nullptr;
  for (const auto &ext : cls.extends) {
    const ast::ClassDef *base =
        resolveClass(ext.base, cls.parent, cls.file, /*report=*/false);
    if (base && base != &cls && (found = memberClass(*base, name)))
      break;
  }
  --importDepth_;
  return found;
}

const ast::Component *ClassTable::memberComponent(const ast::ClassDef &cls,
                                                  const std::string &name,
                                                  const ast::ClassDef **owner) {
  for (const auto &c : cls.components)
    if (c.name == name) {
      *owner = &cls;
      return &c;
    }
  if (importDepth_ > 32)
    return nullptr;
  ++importDepth_;
  const ast::Component *found = nullptr;
  for (const auto &ext : cls.extends) {
    const ast::ClassDef *base =
        resolveClass(ext.base, cls.parent, cls.file, /*report=*/false);
    if (base && base != &cls && (found = memberComponent(*base, name, owner)))
      break;
  }
  --importDepth_;
  return found;
}

LexicalHit ClassTable::lookupIn(const std::string &name,
                                const ast::ClassDef &cls) {
  if (const ast::ClassDef *c = memberClass(cls, name))
    return {c, nullptr, nullptr};
  const ast::ClassDef *owner = nullptr;
  if (const ast::Component *comp = memberComponent(cls, name, &owner))
    return {nullptr, comp, owner};
  return {};
}

LexicalHit ClassTable::lookupImports(const std::string &name,
                                     const ast::ClassDef &cls) {
  if (importDepth_ > 32)
    return {};
  for (const ast::Import &imp : cls.imports) {
    if (imp.path.empty())
      continue;
    ast::Name path;
    path.parts = imp.path;
    path.loc = imp.loc;
    bool matches = imp.wildcard || (!imp.alias.empty() && imp.alias == name) ||
                   (imp.alias.empty() && imp.names.empty() &&
                    imp.path.back() == name) ||
                   std::find(imp.names.begin(), imp.names.end(), name) !=
                       imp.names.end();
    if (!matches)
      continue;
    ++importDepth_;
    // Import paths are always global: resolved from the file's top level.
    const ast::ClassDef *target =
        resolveClass(path, nullptr, cls.file, /*report=*/false);
    if (!target && !imp.wildcard && imp.names.empty() &&
        imp.path.size() > 1) {
      // `import Modelica.Constants.k`: a constant of a package, not a
      // class (MSL's Semiconductors package imports Boltzmann's constant).
      ast::Name package;
      package.parts.assign(imp.path.begin(), imp.path.end() - 1);
      package.loc = imp.loc;
      const ast::ClassDef *owner =
          resolveClass(package, nullptr, cls.file, /*report=*/false);
      --importDepth_;
      if (owner) {
        LexicalHit hit = lookupIn(imp.path.back(), *owner);
        if (hit.comp)
          return hit;
      }
      continue;
    }
    --importDepth_;
    if (!target)
      continue;
    if (imp.wildcard || !imp.names.empty()) {
      LexicalHit hit = lookupIn(name, *target);
      if (hit.cls || hit.comp)
        return hit;
      continue;
    }
    return {target, nullptr, nullptr};
  }
  return {};
}

LexicalHit ClassTable::lookup(const std::string &name,
                              const ast::ClassDef *scope, uint32_t fileId) {
  bool encapsulated = false;
  for (const ast::ClassDef *c = scope; c; c = c->parent) {
    LexicalHit hit = lookupIn(name, *c);
    if (hit.cls || hit.comp)
      return hit;
    hit = lookupImports(name, *c);
    if (hit.cls || hit.comp)
      return hit;
    if (c->encapsulated) {
      encapsulated = true;
      break;
    }
  }
  if (!encapsulated)
    if (const ast::ClassDef *top = topLevel(fileId, name))
      return {top, nullptr, nullptr};
  if (const ast::ClassDef *lib = libraryPackage(name))
    return {lib, nullptr, nullptr};
  return {};
}

void ClassTable::reportOnce(DiagId id, SourceRange range,
                            std::vector<std::string> args) {
  std::string key = diagnosticKey(id, range, args);
  if (reported_.insert(key).second)
    diags_.report(id, range, std::move(args));
}

const ast::ClassDef *ClassTable::resolveClass(const ast::Name &name,
                                              const ast::ClassDef *scope,
                                              uint32_t fileId, bool report) {
  if (name.parts.empty())
    return nullptr;
  LexicalHit hit = name.global ? LexicalHit{topLevel(fileId, name.parts[0])}
                               : lookup(name.parts[0], scope, fileId);
  if (!hit.cls && name.global)
    hit.cls = libraryPackage(name.parts[0]);
  const ast::ClassDef *cls = hit.cls;
  if (!cls) {
    if (report) {
      std::vector<std::string> names;
      visibleNames(scope, fileId, names);
      std::string best = closestName(name.parts[0], names);
      if (best.empty())
        reportOnce(DiagId::ErrUndefinedClass,
                      SourceRange{name.loc, name.length}, {name.parts[0]});
      else
        reportOnce(DiagId::ErrUndefinedClassSuggest,
                      SourceRange{name.loc, name.length}, {name.parts[0], best});
    }
    return nullptr;
  }
  for (size_t i = 1; i < name.parts.size(); ++i) {
    const ast::ClassDef *next = memberClass(*cls, name.parts[i]);
    if (!next) {
      if (report) {
        std::vector<std::string> names;
        for (const auto &c : cls->classes)
          names.push_back(c->name);
        std::string best = closestName(name.parts[i], names);
        if (best.empty())
          reportOnce(DiagId::ErrNoMemberClass,
                        SourceRange{name.loc, name.length},
                        {name.parts[i], cls->qualifiedName()});
        else
          reportOnce(DiagId::ErrNoMemberClassSuggest,
                        SourceRange{name.loc, name.length},
                        {name.parts[i], cls->qualifiedName(), best});
      }
      return nullptr;
    }
    cls = next;
  }
  return cls;
}

void ClassTable::visibleNames(const ast::ClassDef *scope, uint32_t fileId,
                              std::vector<std::string> &out) const {
  for (const ast::ClassDef *c = scope; c; c = c->parent) {
    for (const auto &k : c->classes)
      out.push_back(k->name);
    for (const auto &comp : c->components)
      out.push_back(comp.name);
    for (const auto &imp : c->imports)
      if (!imp.alias.empty())
        out.push_back(imp.alias);
      else if (!imp.path.empty() && !imp.wildcard)
        out.push_back(imp.path.back());
  }
  if (const ast::StoredDefinition *f = file(fileId))
    for (const auto &c : f->classes)
      out.push_back(c->name);
  for (const char *b : {"Real", "Integer", "Boolean", "String"})
    out.push_back(b);
  for (const auto &[name, cls] : library_)
    if (cls)
      out.push_back(name);
  for (const std::string &dir : libraryPaths_) {
    std::error_code ec;
    for (const auto &entry : std::filesystem::directory_iterator(dir, ec))
      if (entry.path().extension() == ".lsd")
        out.push_back(entry.path().stem().string());
  }
}

std::string closestName(const std::string &name,
                        const std::vector<std::string> &candidates) {
  std::string best;
  // One- and two-letter names only match a letter more or less ('RR' for
  // 'R'), never a different letter ('y' is not a typo of 'B'); three
  // letters tolerate one edit; longer ones a third of their length (two at
  // least, so a swapped pair of letters is found).
  if (name.size() <= 2) {
    std::string best;
    for (const std::string &c : candidates)
      if (c != name && c.size() != name.size() && c.size() <= name.size() + 1 &&
          editDistance(name, c) == 1 && (best.empty() || c < best))
        best = c;
    return best;
  }
  size_t bestDist =
      (name.size() == 3 ? 1 : std::max<size_t>(2, name.size() / 3)) + 1;
  for (const std::string &c : candidates) {
    if (c == name || c.empty())
      continue;
    size_t d = editDistance(name, c);
    if (d < bestDist || (d == bestDist && !best.empty() && c < best)) {
      if (d < bestDist || c < best) {
        bestDist = d;
        best = c;
      }
    }
  }
  return best;
}

} // namespace ldae::frontend
