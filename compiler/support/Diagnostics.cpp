#include "Diagnostics.h"
#include "Utf8.h"

#include <fmt/args.h>
#include <fmt/format.h>

#include <ostream>

namespace ldae {

namespace {
struct DiagInfo {
  Severity severity;
  const char *format;
};

constexpr DiagInfo kDiagTable[] = {
#define DIAG(Id, Sev, Fmt) {Severity::Sev, Fmt},
#include "Diagnostics.def"
#undef DIAG
};

const char *severityName(Severity s) {
  switch (s) {
  case Severity::Note:
    return "note";
  case Severity::Warning:
    return "warning";
  case Severity::Error:
    return "error";
  }
  return "error";
}
} // namespace

Severity DiagnosticEngine::severityOf(DiagId id) {
  return kDiagTable[static_cast<size_t>(id)].severity;
}

std::string DiagnosticEngine::format(DiagId id,
                                     const std::vector<std::string> &args) {
  fmt::dynamic_format_arg_store<fmt::format_context> store;
  for (const std::string &a : args)
    store.push_back(a);
  try {
    return fmt::vformat(kDiagTable[static_cast<size_t>(id)].format, store);
  } catch (const fmt::format_error &) {
    // A row asking for more arguments than given is a compiler bug; show
    // the raw format rather than losing the diagnostic.
    return kDiagTable[static_cast<size_t>(id)].format;
  }
}

Diagnostic &DiagnosticEngine::report(DiagId id, SourceRange range,
                                     std::vector<std::string> args) {
  Severity sev = severityOf(id);
  if (sev == Severity::Error) {
    if (errorLimit_ != 0 && errors_ >= errorLimit_) {
      sink_ = Diagnostic{};
      return sink_;
    }
    ++errors_;
  }
  diags_.push_back(Diagnostic{id, sev, range, format(id, args), {}});
  if (sev == Severity::Error && errorLimit_ != 0 && errors_ == errorLimit_) {
    Diagnostic &last = diags_.back();
    addNote(last, SourceLoc{}, DiagId::NoteGeneric,
            {"too many errors; stopping here"});
  }
  return diags_.back();
}

void DiagnosticEngine::addNote(Diagnostic &parent, SourceRange range,
                               DiagId id, std::vector<std::string> args) {
  parent.notes.push_back(
      Diagnostic{id, Severity::Note, range, format(id, args), {}});
}

static void renderOne(const SourceManager &sources, const Diagnostic &d,
                      Severity shownAs, std::string &out) {
  const SourceLoc &loc = d.range.begin;
  if (loc.valid())
    out += sources.describe(loc) + ": ";
  else
    out += "ldaec: ";
  out += severityName(shownAs);
  out += ": ";
  out += d.message;
  out += '\n';
  if (!loc.valid())
    return;
  std::string_view line = sources.lineText(loc.file, loc.line);
  if (line.empty())
    return;
  // Columns count characters, not bytes: walk the line one UTF-8 sequence
  // at a time, printing invalid bytes as U+FFFD so the output stays valid
  // UTF-8. Tabs in the source keep their width under the caret.
  std::string caret;
  uint32_t col = 1;
  for (size_t i = 0; i < line.size(); ++col) {
    utf8::Char c = utf8::decodeAt(line, i);
    utf8::append(out, c.cp);
    if (col < loc.col)
      caret += c.cp == '\t' ? '\t' : ' ';
    i += c.bytes;
  }
  out += '\n';
  caret += '^';
  for (uint32_t i = 1; i < d.range.length; ++i)
    caret += '~';
  out += caret;
  out += '\n';
}

std::string DiagnosticEngine::render(const Diagnostic &d) const {
  std::string out;
  renderOne(sources_, d, d.severity, out);
  for (const Diagnostic &n : d.notes)
    renderOne(sources_, n, Severity::Note, out);
  return out;
}

std::string diagnosticKey(DiagId id, const SourceRange &range,
                          const std::vector<std::string> &args) {
  std::string key = std::to_string(static_cast<int>(id)) + ":" +
                    std::to_string(range.begin.file) + ":" +
                    std::to_string(range.begin.line) + ":" +
                    std::to_string(range.begin.col);
  for (const std::string &a : args)
    key += ":" + a;
  return key;
}

void DiagnosticEngine::flush(std::ostream &out) {
  for (; printed_ < diags_.size(); ++printed_)
    out << render(diags_[printed_]);
  out.flush();
}

} // namespace ldae
