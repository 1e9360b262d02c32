// Libraries on disk, parsed when first referenced (MLS 13.4, and the
// MODELICAPATH of the Modelica tools): a top-level name is looked up on the
// library path as `Name/package.mo` (a directory package), `Name.mo`,
// `Name VERSION/package.mo`, `Name VERSION.mo` or ldaec's own `Name.lsd`;
// a directory package's children that its package.mo does not hold are
// `Child.mo` or `Child/package.mo` beside it. A small model that uses the
// Modelica Standard Library parses the few files on its way, not the
// library's 2,554 (docs/frontend.md, "Libraries").
#pragma once

#include "frontend/Ast.h"
#include "support/Diagnostics.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ldae::frontend {

class LibraryLoader {
public:
  /// Takes each file the loader parses (the class table owns the ASTs).
  using Keep = std::function<void(std::unique_ptr<ast::StoredDefinition>)>;

  LibraryLoader(SourceManager &sources, DiagnosticEngine &diags,
                std::vector<std::string> paths, Keep keep);

  /// The top-level class `name` from the first library directory that has
  /// it, or null.
  const ast::ClassDef *topLevel(const std::string &name);
  /// The child `name` of the directory package `pkg` from its own file, or
  /// null (not a directory package, or no such file).
  const ast::ClassDef *child(const ast::ClassDef &pkg, const std::string &name);
  /// The files parsed so far (for the docs' loading figures and tests).
  size_t filesParsed() const { return filesParsed_; }

private:
  /// Parses `file` and returns its class `name` (its parent set to
  /// `parent`), recording `dir` as the class's directory when the file is
  /// a package.mo.
  const ast::ClassDef *load(const std::string &file, const std::string &name,
                            ast::ClassDef *parent, const std::string &dir);

  SourceManager &sources_;
  DiagnosticEngine &diags_;
  std::vector<std::string> paths_;
  Keep keep_;
  std::map<const ast::ClassDef *, std::string> dirOf_;
  std::map<std::pair<const ast::ClassDef *, std::string>, const ast::ClassDef *>
      children_;
  size_t filesParsed_ = 0;
};

/// The library directories of `--lib` (in order), then of the
/// MODELICAPATH environment variable (`:`-separated), then ldaec's own.
std::vector<std::string> libraryPath(const std::vector<std::string> &libs,
                                     const std::string &ownLibrary);

} // namespace ldae::frontend
