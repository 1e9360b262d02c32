// Classes by name: the parsed files, the standard library (one package per
// file under the library paths, parsed on first use) and the lexical lookup
// rules of LANGUAGE.md: the class, its enclosing classes (with their
// imports), the file's top level, then the library.
#pragma once

#include "frontend/Ast.h"
#include "frontend/LibraryLoader.h"
#include "support/Diagnostics.h"

#include <map>
#include <set>
#include <memory>
#include <string>
#include <vector>

namespace ldae::frontend {

/// The result of a lexical lookup: a class, or a component declared in a
/// class (a package constant), or nothing.
struct LexicalHit {
  const ast::ClassDef *cls = nullptr;
  const ast::Component *comp = nullptr;
  const ast::ClassDef *owner = nullptr; // class declaring `comp`
};

class ClassTable {
public:
  ClassTable(SourceManager &sources, DiagnosticEngine &diags,
             std::vector<std::string> libraryPaths);

  /// Adds a parsed file; its top-level classes are visible from it.
  void addFile(std::unique_ptr<ast::StoredDefinition> file);
  const ast::StoredDefinition *file(uint32_t fileId) const;

  /// Looks up the first part of a name from inside class `scope` of file
  /// `fileId` (scope null: the file's top level).
  LexicalHit lookup(const std::string &name, const ast::ClassDef *scope,
                    uint32_t fileId);
  /// A class nested in `cls` (or inherited from its bases) by name.
  const ast::ClassDef *memberClass(const ast::ClassDef &cls,
                                   const std::string &name);
  /// A component declared in `cls` (or its bases) by name.
  const ast::Component *memberComponent(const ast::ClassDef &cls,
                                        const std::string &name,
                                        const ast::ClassDef **owner);
  /// Resolves a dotted class name; reports and returns null if not found.
  const ast::ClassDef *resolveClass(const ast::Name &name,
                                    const ast::ClassDef *scope, uint32_t fileId,
                                    bool report = true);
  /// The library files parsed so far.
  size_t libraryFilesParsed() const { return loader_.filesParsed(); }
  /// Names visible from `scope`, for "did you mean".
  void visibleNames(const ast::ClassDef *scope, uint32_t fileId,
                    std::vector<std::string> &out) const;

private:
  const ast::ClassDef *libraryPackage(const std::string &name);
  const ast::ClassDef *topLevel(uint32_t fileId, const std::string &name) const;
  LexicalHit lookupImports(const std::string &name, const ast::ClassDef &cls);
  LexicalHit lookupIn(const std::string &name, const ast::ClassDef &cls);

  void reportOnce(DiagId id, SourceRange range, std::vector<std::string> args);

  SourceManager &sources_;
  DiagnosticEngine &diags_;
  std::vector<std::string> libraryPaths_;
  std::vector<std::unique_ptr<ast::StoredDefinition>> files_;
  std::map<std::string, const ast::ClassDef *> library_; // null: not found
  LibraryLoader loader_;
  unsigned importDepth_ = 0;
  std::set<std::string> reported_;
};

/// The closest of `candidates` to `name` by edit distance, or "".
std::string closestName(const std::string &name,
                        const std::vector<std::string> &candidates);

} // namespace ldae::frontend
