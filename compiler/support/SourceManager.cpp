#include "SourceManager.h"

#include <fstream>
#include <sstream>

namespace ldae {

uint32_t SourceManager::addFile(std::string path, std::string text) {
  File f{std::move(path), std::move(text), {0}};
  for (uint32_t i = 0; i < f.text.size(); ++i)
    if (f.text[i] == '\n')
      f.lineStarts.push_back(i + 1);
  files_.push_back(std::move(f));
  return static_cast<uint32_t>(files_.size());
}

uint32_t SourceManager::loadFile(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return 0;
  std::ostringstream ss;
  ss << in.rdbuf();
  return addFile(path, ss.str());
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
  uint32_t begin = f.lineStarts[line - 1];
  uint32_t end = line < f.lineStarts.size() ? f.lineStarts[line] - 1
                                            : static_cast<uint32_t>(f.text.size());
  if (end > begin && f.text[end - 1] == '\r')
    --end;
  return std::string_view(f.text).substr(begin, end - begin);
}

std::string SourceManager::describe(SourceLoc loc) const {
  if (!loc.valid())
    return "<builtin>";
  return path(loc.file) + ":" + std::to_string(loc.line) + ":" +
         std::to_string(loc.col);
}

} // namespace ldae
