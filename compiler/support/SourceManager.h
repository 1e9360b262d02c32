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

/// Why loadFile refused a file.
enum class LoadError { None, Unreadable, NotRegularFile, TooLarge };

/// Owns the text of every file read during a compilation. Lines end at
/// "\n", "\r\n" or a lone "\r"; columns count characters (UTF-8 sequences,
/// an invalid byte counting as one), as the lexer does.
class SourceManager {
public:
  /// Largest source file read (64 MiB): a bound on memory for inputs like
  /// /dev/zero or a huge generated file passed by mistake.
  static constexpr uint64_t kMaxFileBytes = uint64_t(64) << 20;

  /// Registers `text` under `path`; returns the file id (>= 1).
  uint32_t addFile(std::string path, std::string text);
  /// Reads `path` from disk; returns 0 and sets `error` (if given) when it
  /// cannot be read, is not a regular file or is larger than kMaxFileBytes.
  uint32_t loadFile(const std::string &path, LoadError *error = nullptr);

  const std::string &path(uint32_t file) const;
  const std::string &text(uint32_t file) const;
  /// The text of 1-based `line` without its line end; empty if out of range.
  std::string_view lineText(uint32_t file, uint32_t line) const;
  /// Just after the last character that is not white space: where
  /// "expected ... before end of file" points, on a line the user can see.
  SourceLoc endOfText(uint32_t file) const;
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
