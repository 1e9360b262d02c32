// Diagnostics: declared once in Diagnostics.def (id, severity, format),
// emitted with structured arguments, drawn clang-style:
//   file:line:col: error: message
//     the source line
//         ^~~~
// followed by notes. Emitting code never builds message text itself.
#pragma once

#include "SourceManager.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace ldae {

enum class Severity { Note, Warning, Error };

enum class DiagId {
#define DIAG(Id, Sev, Fmt) Id,
#include "Diagnostics.def"
#undef DIAG
};

/// One emitted diagnostic with its notes, kept for printing and for tests.
struct Diagnostic {
  DiagId id;
  Severity severity;
  SourceRange range;
  std::string message; // formatted
  std::vector<Diagnostic> notes;
};

/// Collects diagnostics of one compilation and prints them.
class DiagnosticEngine {
public:
  explicit DiagnosticEngine(const SourceManager &sources) : sources_(sources) {}

  /// Reports `id` at `range` with `args` substituted into its format.
  /// Returns the diagnostic so notes can be attached.
  Diagnostic &report(DiagId id, SourceRange range,
                     std::vector<std::string> args = {});
  Diagnostic &report(DiagId id, SourceLoc loc,
                     std::vector<std::string> args = {}) {
    return report(id, SourceRange{loc, 1}, std::move(args));
  }
  /// Attaches a note to `parent`.
  static void addNote(Diagnostic &parent, SourceRange range, DiagId id,
                      std::vector<std::string> args = {});
  static void addNote(Diagnostic &parent, SourceLoc loc, DiagId id,
                      std::vector<std::string> args = {}) {
    addNote(parent, SourceRange{loc, 1}, id, std::move(args));
  }

  /// The files diagnostics point into (for `file:line` inside messages).
  const SourceManager &sources() const { return sources_; }

  unsigned errorCount() const { return errors_; }
  bool hasErrors() const { return errors_ != 0; }
  const std::vector<Diagnostic> &diagnostics() const { return diags_; }
  /// Stops reporting further errors after this many (0: unlimited); the
  /// last one says that the limit was reached.
  void setErrorLimit(unsigned limit) { errorLimit_ = limit; }

  /// Prints every diagnostic not printed yet, in order.
  void flush(std::ostream &out);
  /// Text of one diagnostic as `flush` draws it.
  std::string render(const Diagnostic &d) const;

  static Severity severityOf(DiagId id);
  static std::string format(DiagId id, const std::vector<std::string> &args);

private:
  const SourceManager &sources_;
  std::vector<Diagnostic> diags_;
  size_t printed_ = 0;
  unsigned errors_ = 0;
  unsigned errorLimit_ = 0;
  Diagnostic sink_; // receives reports past the error limit
};

/// Identifies a diagnostic by id, position and arguments, so a stage that
/// reaches the same fault along several paths reports it once.
std::string diagnosticKey(DiagId id, const SourceRange &range,
                          const std::vector<std::string> &args);

/// Quotes a user name for a message: 'x'.
inline std::string quoted(const std::string &name) { return "'" + name + "'"; }

} // namespace ldae
