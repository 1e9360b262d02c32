// Pass "dm": when equations and unknowns cannot be matched, the
// Dulmage–Mendelsohn decomposition names what is wrong in the user's
// terms: which equations over-determine which unknowns ("equations at
// pend.lsd:7 and :9 both determine only 'x'") and which unknowns nothing
// determines. Also used for the initialization system.
#include "passes/Passes.h"
#include "passes/Results.h"

#include "graph/DulmageMendelsohn.h"

#include <algorithm>
#include <tuple>

namespace ldae::passes {

namespace {
constexpr size_t kMaxNotes = 8;

/// "equations at a.lsd:7 and :9" (same file shortened), with the verb.
std::pair<std::string, std::string>
describeRows(PassContext &s, const std::vector<int> &rows,
             const SingularityNames &names) {
  std::string list;
  uint32_t lastFile = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (i > 0)
      list += i + 1 == rows.size() ? " and " : ", ";
    SourceLoc loc = names.rowLoc(rows[i]);
    if (!loc.valid()) {
      list += quoted(names.rowText(rows[i]));
      continue;
    }
    if (loc.file == lastFile)
      list += ":" + std::to_string(loc.line);
    else
      list += s.where(loc);
    lastFile = loc.file;
  }
  if (rows.size() == 1)
    return {"the equation at " + list, "determines"};
  if (rows.size() == 2)
    return {"equations at " + list, "both determine"};
  return {"equations at " + list,
          "all " + std::to_string(rows.size()) + " determine"};
}
} // namespace

bool diagnoseSingular(PassContext &s, const char *system,
                      const graph::BipartiteGraph &g, const graph::Matching &m,
                      const SingularityNames &names,
                      const std::vector<char> &colAllowed, bool record) {
  graph::DmDecomposition dm = graph::dulmageMendelsohn(g, m, colAllowed);
  if (!dm.singular())
    return false;
  std::vector<std::string> under;
  for (int c : dm.under.cols)
    under.push_back(names.colName(c));
  std::vector<graph::DmPart> pieces = graph::connectedPieces(g, dm.over);
  if (record) {
    for (int r : dm.over.rows)
      s.report.overDetermined.push_back(names.rowText(r));
    s.report.underDetermined = under;
  }
  auto addNotes = [&](Diagnostic &d, const std::vector<int> &rows) {
    for (size_t i = 0; i < rows.size() && i < kMaxNotes; ++i)
      DiagnosticEngine::addNote(d, names.rowLoc(rows[i]),
                                DiagId::NoteEquationInvolved,
                                {names.rowText(rows[i])});
  };
  bool first = true;
  for (graph::DmPart &piece : pieces) {
    if (piece.rows.empty())
      continue;
    // In source order, so "pend.lsd:7 and :9" reads like the file.
    std::stable_sort(piece.rows.begin(), piece.rows.end(), [&](int a, int b) {
      SourceLoc la = names.rowLoc(a), lb = names.rowLoc(b);
      return std::tie(la.file, la.line, la.col) <
             std::tie(lb.file, lb.line, lb.col);
    });
    auto [rows, verb] = describeRows(s, piece.rows, names);
    std::vector<std::string> cols;
    for (int c : piece.cols)
      cols.push_back(names.colName(c));
    SourceLoc at = names.rowLoc(piece.rows.front());
    Diagnostic *d;
    if (cols.empty())
      d = &s.diags.report(DiagId::ErrSingularOverEmpty, at,
                          {system, rows, verb});
    else if (first && !under.empty())
      d = &s.diags.report(DiagId::ErrSingularOverUnder, at,
                          {system, rows, verb, quotedFew(cols),
                           quotedFew(under)});
    else
      d = &s.diags.report(DiagId::ErrSingularOver, at,
                          {system, rows, verb, quotedFew(cols)});
    addNotes(*d, piece.rows);
    if (first && !under.empty())
      for (size_t i = 0; i < dm.under.cols.size() && i < kMaxNotes; ++i)
        DiagnosticEngine::addNote(*d, names.colLoc(dm.under.cols[i]),
                                  DiagId::NoteVariableDeclared,
                                  {names.colName(dm.under.cols[i])});
    first = false;
  }
  if (first) {
    Diagnostic &d =
        s.diags.report(DiagId::ErrSingularUnder,
                       names.colLoc(dm.under.cols.front()),
                       {system, quotedFew(under)});
    for (size_t i = 0; i < dm.under.cols.size() && i < kMaxNotes; ++i)
      DiagnosticEngine::addNote(d, names.colLoc(dm.under.cols[i]),
                                DiagId::NoteVariableDeclared,
                                {names.colName(dm.under.cols[i])});
  }
  return true;
}

namespace {

class DmDiagnosisPass
    : public TypedPass<DmDiagnosisPass, Reads<MatchingResult>, Updates<>,
                       Produces<>> {
public:
  DmDiagnosisPass() : TypedPass(PassId::Dm) {}

  bool runOn(PassContext &ctx, const MatchingResult &s) {
    const int rows = s.merged.numRows(), cols = s.merged.numCols;
    if (s.matching.size == rows && s.matching.size == cols)
      return true;
    SingularityNames names;
    names.rowLoc = [&](int r) {
      return ctx.model.equations[s.equations[r]].loc;
    };
    names.rowText = [&](int r) { return ctx.equationText(s.equations[r]); };
    names.colName = [&](int c) {
      return ctx.model.variables[s.unknowns[c]].name;
    };
    names.colLoc = [&](int c) {
      return ctx.model.variables[s.unknowns[c]].loc;
    };
    diagnoseSingular(ctx, "model", s.merged, s.matching, names, {}, true);
    ctx.report.singular = true;
    return false;
  }
};

} // namespace

std::unique_ptr<Pass> createDmDiagnosisPass() {
  return std::make_unique<DmDiagnosisPass>();
}

} // namespace ldae::passes
