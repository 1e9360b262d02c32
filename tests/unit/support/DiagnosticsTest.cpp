// Diagnostics are drawn clang-style: location, severity, message, the source
// line and a caret with a `~~~` range, then notes.
#include "support/Diagnostics.h"

#include <gtest/gtest.h>

using namespace ldae;

TEST(Diagnostics, RendersLocationLineCaretAndRange) {
  SourceManager sm;
  uint32_t f = sm.addFile("pend.lsd", "model P\n  Real x;\n  x = 1 +;\nend P;\n");
  DiagnosticEngine diags(sm);
  Diagnostic &d = diags.report(DiagId::ErrorGeneric,
                               SourceRange{{f, 3, 3}, 5}, {"bad thing"});
  DiagnosticEngine::addNote(d, SourceLoc{f, 2, 8}, DiagId::NoteGeneric,
                            {"declared here"});
  EXPECT_EQ(diags.render(d), "pend.lsd:3:3: error: bad thing\n"
                             "  x = 1 +;\n"
                             "  ^~~~~\n"
                             "pend.lsd:2:8: note: declared here\n"
                             "  Real x;\n"
                             "       ^\n");
  EXPECT_EQ(diags.errorCount(), 1u);
}

TEST(Diagnostics, WithoutLocationNamesTheTool) {
  SourceManager sm;
  DiagnosticEngine diags(sm);
  diags.report(DiagId::ErrCannotReadFile, SourceLoc{}, {"missing.lsd"});
  EXPECT_EQ(diags.render(diags.diagnostics()[0]),
            "ldaec: error: cannot read file 'missing.lsd'\n");
}

TEST(Diagnostics, ErrorLimitStopsReporting) {
  SourceManager sm;
  DiagnosticEngine diags(sm);
  diags.setErrorLimit(2);
  for (int i = 0; i < 5; ++i)
    diags.report(DiagId::ErrorGeneric, SourceLoc{}, {"e"});
  EXPECT_EQ(diags.errorCount(), 2u);
  ASSERT_EQ(diags.diagnostics().size(), 2u);
  EXPECT_EQ(diags.diagnostics()[1].notes.size(), 1u);
}

TEST(SourceManager, LinesWithoutNewlinesAndCarriageReturns) {
  SourceManager sm;
  // LF, CRLF and a lone CR (old Mac files) all end a line.
  uint32_t f = sm.addFile("a.lsd", "one\r\ntwo\nthree\rfour");
  EXPECT_EQ(sm.lineText(f, 1), "one");
  EXPECT_EQ(sm.lineText(f, 2), "two");
  EXPECT_EQ(sm.lineText(f, 3), "three");
  EXPECT_EQ(sm.lineText(f, 4), "four");
  EXPECT_EQ(sm.lineText(f, 5), "");
  EXPECT_EQ(sm.describe({f, 2, 5}), "a.lsd:2:5");
}
