// Libraries on disk (see LibraryLoader.h).
#include "frontend/LibraryLoader.h"
#include "frontend/Frontend.h"
#include "frontend/Parser.h"

#include <cstdlib>
#include <filesystem>

namespace ldae::frontend {

namespace fs = std::filesystem;

namespace {

bool isFile(const fs::path &p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

/// A name that can be a file name: no path separators, not quoted.
bool plainName(const std::string &name) {
  return !name.empty() && name.front() != '\'' &&
         name.find_first_of("/\\.") == std::string::npos;
}

} // namespace

LibraryLoader::LibraryLoader(SourceManager &sources, DiagnosticEngine &diags,
                             std::vector<std::string> paths, Keep keep)
    : sources_(sources), diags_(diags), paths_(std::move(paths)),
      keep_(std::move(keep)) {}

const ast::ClassDef *LibraryLoader::load(const std::string &file,
                                         const std::string &name,
                                         ast::ClassDef *parent,
                                         const std::string &dir) {
  LoadError error = LoadError::None;
  uint32_t id = sources_.loadFile(file, &error);
  if (id == 0) {
    reportLoadError(diags_, file, error);
    return nullptr;
  }
  auto def = parseFile(id, sources_, diags_);
  if (!def)
    return nullptr;
  ++filesParsed_;
  // The file's `within` names the package it was found in.
  std::string expected = parent ? parent->qualifiedName() : "";
  std::string said = def->hasWithin ? def->within.str() : expected;
  if (said != expected) {
    auto describe = [](const std::string &pkg) {
      return pkg.empty() ? std::string("the top level") : "'" + pkg + "'";
    };
    diags_.report(DiagId::WarnWithinMismatch,
                  SourceRange{def->within.loc, def->within.length},
                  {fs::path(file).filename().string(), describe(said),
                   describe(expected)});
  }
  ast::ClassDef *found = nullptr;
  for (auto &c : def->classes)
    if (c->name == name)
      found = c.get();
  if (found) {
    // Lexically nested in its package, as if written inside it.
    found->parent = parent;
    if (!dir.empty())
      dirOf_[found] = dir;
  }
  keep_(std::move(def));
  return found;
}

const ast::ClassDef *LibraryLoader::topLevel(const std::string &name) {
  if (!plainName(name))
    return nullptr;
  for (const std::string &root : paths_) {
    fs::path base(root);
    if (isFile(base / name / "package.mo"))
      return load((base / name / "package.mo").string(), name, nullptr,
                  (base / name).string());
    if (isFile(base / (name + ".mo")))
      return load((base / (name + ".mo")).string(), name, nullptr, "");
    if (isFile(base / (name + ".lsd")))
      return load((base / (name + ".lsd")).string(), name, nullptr, "");
    // `Name VERSION`: the first such entry (MLS 13.4.3 leaves the choice
    // among versions to the tool).
    std::error_code ec;
    for (const auto &entry : fs::directory_iterator(base, ec)) {
      std::string file = entry.path().filename().string();
      if (file.rfind(name + " ", 0) != 0)
        continue;
      if (isFile(entry.path() / "package.mo"))
        return load((entry.path() / "package.mo").string(), name, nullptr,
                    entry.path().string());
      if (entry.path().extension() == ".mo" && isFile(entry.path()))
        return load(entry.path().string(), name, nullptr, "");
    }
  }
  return nullptr;
}

const ast::ClassDef *LibraryLoader::child(const ast::ClassDef &pkg,
                                          const std::string &name) {
  auto dir = dirOf_.find(&pkg);
  if (dir == dirOf_.end() || !plainName(name))
    return nullptr;
  auto key = std::make_pair(&pkg, name);
  if (auto it = children_.find(key); it != children_.end())
    return it->second;
  children_[key] = nullptr; // guards against re-entry while parsing
  fs::path base(dir->second);
  // The parent is the package itself: a child's lexical lookup goes up
  // through it (ClassTable::lookup).
  auto *parent = const_cast<ast::ClassDef *>(&pkg);
  const ast::ClassDef *found = nullptr;
  if (isFile(base / name / "package.mo"))
    found = load((base / name / "package.mo").string(), name, parent,
                 (base / name).string());
  else if (isFile(base / (name + ".mo")))
    found = load((base / (name + ".mo")).string(), name, parent, "");
  children_[key] = found;
  return found;
}

std::vector<std::string> libraryPath(const std::vector<std::string> &libs,
                                     const std::string &ownLibrary) {
  std::vector<std::string> path = libs;
  if (const char *env = std::getenv("MODELICAPATH")) {
    std::string all = env;
    size_t start = 0;
    while (start <= all.size()) {
      size_t colon = all.find(':', start);
      std::string dir = all.substr(start, colon - start);
      if (!dir.empty())
        path.push_back(dir);
      if (colon == std::string::npos)
        break;
      start = colon + 1;
    }
  }
  path.push_back(ownLibrary);
  return path;
}

} // namespace ldae::frontend
