#include "SourceManager.h"
#include "Utf8.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace ldae {

uint32_t SourceManager::addFile(std::string path, std::string text) {
  File f{std::move(path), std::move(text), {0}};
  const std::string &t = f.text;
  for (uint32_t i = 0; i < t.size(); ++i)
    if (t[i] == '\n' || (t[i] == '\r' && (i + 1 == t.size() || t[i + 1] != '\n')))
      f.lineStarts.push_back(i + 1);
  files_.push_back(std::move(f));
  return static_cast<uint32_t>(files_.size());
}

uint32_t SourceManager::loadFile(const std::string &path, LoadError *error) {
  auto fail = [&](LoadError e) {
    if (error)
      *error = e;
    return 0u;
  };
  // A device or a pipe (/dev/zero, a FIFO) could be read forever: only
  // regular files, and only up to the size limit even if one grows.
  std::error_code ec;
  std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st))
    return fail(LoadError::Unreadable);
  if (!std::filesystem::is_regular_file(st))
    return fail(LoadError::NotRegularFile);
  uint64_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxFileBytes)
    return fail(LoadError::TooLarge);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return fail(LoadError::Unreadable);
  std::string text;
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, static_cast<size_t>(in.gcount()));
    if (text.size() > kMaxFileBytes)
      return fail(LoadError::TooLarge);
  }
  if (in.bad())
    return fail(LoadError::Unreadable);
  if (error)
    *error = LoadError::None;
  return addFile(path, std::move(text));
}

const std::string &SourceManager::path(uint32_t file) const {
  static const std::string none = "<unknown>";
  return file >= 1 && file <= files_.size() ? files_[file - 1].path : none;
}

const std::string &SourceManager::text(uint32_t file) const {
  static const std::string none;
  return file >= 1 && file <= files_.size() ? files_[file - 1].text : none;
}

std::string_view SourceManager::lineText(uint32_t file, uint32_t line) const {
  if (file < 1 || file > files_.size())
    return {};
  const File &f = files_[file - 1];
  if (line < 1 || line > f.lineStarts.size())
    return {};
  size_t begin = f.lineStarts[line - 1];
  size_t end = f.text.find_first_of("\r\n", begin);
  if (end == std::string::npos)
    end = f.text.size();
  return std::string_view(f.text).substr(begin, end - begin);
}

SourceLoc SourceManager::endOfText(uint32_t file) const {
  if (file < 1 || file > files_.size())
    return {};
  const File &f = files_[file - 1];
  size_t last = f.text.find_last_not_of(" \t\r\n\f");
  if (last == std::string::npos)
    return SourceLoc{file, 1, 1};
  // The line holding `last`: the last line start at or before it.
  auto it = std::upper_bound(f.lineStarts.begin(), f.lineStarts.end(),
                             static_cast<uint32_t>(last));
  auto line = static_cast<uint32_t>(it - f.lineStarts.begin());
  std::string_view before =
      std::string_view(f.text).substr(f.lineStarts[line - 1],
                                      last + 1 - f.lineStarts[line - 1]);
  return SourceLoc{file, line,
                   static_cast<uint32_t>(utf8::countChars(before) + 1)};
}

std::string SourceManager::describe(SourceLoc loc) const {
  if (!loc.valid())
    return "<builtin>";
  return path(loc.file) + ":" + std::to_string(loc.line) + ":" +
         std::to_string(loc.col);
}

} // namespace ldae
