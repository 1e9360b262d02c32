// Small helpers for the runtime tests: reading reference CSV tables and
// looking up result columns.
#pragma once

#include "ldae/Simulation.h"

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace testutil {

/// A CSV table with a header line (numbers only below it).
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int col(const std::string &name) const {
    for (size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name)
        return int(i);
    return -1;
  }
};

inline Table readCsv(const std::string &path) {
  Table t;
  std::ifstream f(path);
  std::string line;
  if (!std::getline(f, line))
    return t;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');)
    t.columns.push_back(c);
  while (std::getline(f, line)) {
    std::stringstream ls(line);
    std::vector<double> row;
    for (std::string c; std::getline(ls, c, ',');)
      row.push_back(std::stod(c));
    t.rows.push_back(row);
  }
  return t;
}

inline int column(const ldae::runtime::SimResult &r, const std::string &n) {
  for (size_t i = 0; i < r.columns.size(); ++i)
    if (r.columns[i] == n)
      return int(i);
  return -1;
}

inline std::string referencePath(const std::string &file) {
  return std::string(LDAE_SOURCE_DIR) + "/tests/models/reference/" + file;
}

} // namespace testutil
