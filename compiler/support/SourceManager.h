// Source files and locations. Every diagnostic, variable and equation points
// back into a file registered here, so messages can show the user's own line.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ldae {

/// A position in a source file: 1-based line and column. `file == 0` means
/// "no location" (a compiler-made entity the user did not write).
struct SourceLoc {
  uint32_t file = 0;
  uint32_t line = 0;
  uint32_t col = 0;

  bool valid() const { return file != 0; }
  friend bool operator==(const SourceLoc &, const SourceLoc &) = default;
};

/// A half-open range of columns on one line, for the `~~~` underline.
struct SourceRange {
  SourceLoc begin;
  uint32_t length = 1;
};

/// Owns the text of every file read during a compilation.
class SourceManager {
public:
  /// Registers `text` under `path`; returns the file id (>= 1).
  uint32_t addFile(std::string path, std::string text);
  /// Reads `path` from disk; returns 0 if it cannot be read.
  uint32_t loadFile(const std::string &path);

  const std::string &path(uint32_t file) const;
  const std::string &text(uint32_t file) const;
  /// The text of 1-based `line` without its newline; empty if out of range.
  std::string_view lineText(uint32_t file, uint32_t line) const;
  /// "file:line:col" for messages.
  std::string describe(SourceLoc loc) const;

private:
  struct File {
    std::string path;
    std::string text;
    std::vector<uint32_t> lineStarts;
  };
  std::vector<File> files_; // files_[id - 1]
};

} // namespace ldae
