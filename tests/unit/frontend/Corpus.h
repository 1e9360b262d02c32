// The .lsd files of the source tree that the frontend tests feed on, read
// in a fixed order so every machine runs the same cases.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

namespace ldae {

/// Every .lsd file under the given folders of the source tree.
inline std::vector<std::string>
readTestCorpus(std::initializer_list<const char *> dirs) {
  std::vector<std::string> corpus;
  std::string root = LDAE_SOURCE_DIR;
  for (const char *dir : dirs) {
    std::error_code ec;
    for (const auto &entry :
         std::filesystem::recursive_directory_iterator(root + dir, ec)) {
      if (entry.path().extension() != ".lsd")
        continue;
      std::ifstream in(entry.path());
      std::stringstream ss;
      ss << in.rdbuf();
      corpus.push_back(ss.str());
    }
  }
  std::sort(corpus.begin(), corpus.end()); // same order on every machine
  return corpus;
}

} // namespace ldae
