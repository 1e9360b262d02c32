// The frontend's public interface: an .lsd file in, a flat ir::Model out.
// Parsing, name lookup, extends and modifiers, arrays, function inlining,
// connection sets and equation flattening all happen behind compileFile.
#pragma once

#include "ir/Model.h"
#include "support/Diagnostics.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ldae::frontend {

/// One `--param name=value`, as the driver checks it and the flattener
/// applies it.
struct ParamOverride {
  std::string name;            // trailing blanks dropped; empty: no `name=`
  std::string text;            // what follows the first '='
  std::optional<double> value; // `true`/`false` are 1/0; none: not a finite number
};
ParamOverride parseParamOverride(const std::string &option);

struct FrontendOptions {
  std::string modelName;                   // --model, empty = last non-partial
  std::vector<std::string> paramOverrides; // "name=value"
  /// --lib directories; then MODELICAPATH's, then ldaec's own library
  /// (LibraryLoader.h).
  std::vector<std::string> libraryPaths;
  /// Where the compiled C code of external functions is kept (the JIT's
  /// cache directory); "": a private temporary directory.
  std::string cacheDir;
};

/// Parses, checks and flattens `path`; nullptr after reporting errors.
std::unique_ptr<ir::Model> compileFile(const std::string &path,
                                       const FrontendOptions &opts,
                                       SourceManager &sources,
                                       DiagnosticEngine &diags);

/// Reports why `path` could not be loaded (unreadable, not a regular file,
/// over SourceManager::kMaxFileBytes), naming the file.
void reportLoadError(DiagnosticEngine &diags, const std::string &path,
                     LoadError error);

/// Same for source text already in memory (tests, the fuzzer): registers
/// `text` under the name `path`.
std::unique_ptr<ir::Model> compileSource(const std::string &path,
                                         std::string text,
                                         const FrontendOptions &opts,
                                         SourceManager &sources,
                                         DiagnosticEngine &diags);

/// der() of a discrete variable (Integer, Boolean, discrete Real, an event
/// input or a variable a when-clause assigns): an error at the equation,
/// with the variable's declaration as a note. Returns false if any.
bool checkDiscreteDerivatives(const ir::Model &model, DiagnosticEngine &diags);

/// An unknown without a start value that an initial equation gives a
/// value (linear in it, reading parameters only) starts at that value.
void startFromInitialEquations(ir::Model &model);

/// Equation/unknown count check: a warning saying how many of each and
/// which components they come from (the geometric algorithm gives the
/// verdict, docs/sga.md). Returns true if balanced.
bool checkBalance(const ir::Model &model, DiagnosticEngine &diags);

} // namespace ldae::frontend
