// The OpenModelica/Dymola result layout on a MatFile (see MatResult.h).
// Written from OpenModelica's user's guide, "The MATv4 Result File
// Format": in the transposed layout ("binTrans") each stored matrix is the
// transpose of the documented one, so a row of data_2 on disk is one time
// point and each name is one column of `name`.
#include "MatResult.h"
#include "MatFile.h"

#include <unordered_map>

namespace ldae::runtime {

namespace {

/// One row of dataInfo: where a variable's values are.
struct Where {
  int block;         ///< 0 time (the abscissa), 1 data_1, 2 data_2
  int index;         ///< 1-based row of the block; negative: minus it
  int interpolation; ///< 0: linear
  int extrapolation; ///< -1: undefined outside the time range, 0: hold
};

/// "description [unit]", as OpenModelica writes its descriptions.
std::string describe(const std::string &description, const std::string &unit) {
  if (unit.empty())
    return description;
  return description.empty() ? "[" + unit + "]"
                             : description + " [" + unit + "]";
}

/// The variables of the file in order, and what goes in each block.
struct Layout {
  std::vector<std::string> names, descriptions;
  std::vector<Where> where;
  std::vector<int> stored;        ///< result columns in data_2, time first
  std::vector<double> paramValues; ///< data_1 rows after time
};

Layout layOut(const SimResult &r) {
  Layout l;
  std::unordered_map<std::string, int> paramRow; // name -> data_1 row
  for (size_t k = 0; k < r.params.size(); ++k) {
    paramRow.emplace(r.params[k].name, int(k) + 2); // row 1 is time
    l.paramValues.push_back(r.params[k].value);
  }
  auto info = [&](size_t c) {
    return c < r.info.size() ? r.info[c] : ColumnInfo{};
  };
  // data_2 rows of the stored columns, to resolve aliases in one pass.
  std::vector<int> storedRow(r.columns.size(), 0);
  for (size_t c = 0; c < r.columns.size(); ++c) {
    ColumnInfo ci = info(c);
    bool param = ci.kind == ColumnKind::Parameter &&
                 paramRow.count(r.columns[c]) > 0;
    if (c == 0 || (!param && ci.alias == 0)) {
      l.stored.push_back(int(c));
      storedRow[c] = int(l.stored.size());
    }
  }
  std::unordered_map<std::string, bool> named;
  for (size_t c = 0; c < r.columns.size(); ++c) {
    ColumnInfo ci = info(c);
    l.names.push_back(r.columns[c]);
    named[r.columns[c]] = true;
    if (c == 0) {
      l.descriptions.push_back(describe("Simulation time", "s"));
      l.where.push_back({0, 1, 0, -1});
      continue;
    }
    l.descriptions.push_back(describe(ci.description, ci.unit));
    if (auto p = paramRow.find(r.columns[c]);
        ci.kind == ColumnKind::Parameter && p != paramRow.end()) {
      l.where.push_back({1, p->second, 0, 0});
    } else if (ci.alias != 0 && storedRow[std::abs(ci.alias) - 1] > 0) {
      int row = storedRow[std::abs(ci.alias) - 1];
      l.where.push_back({2, ci.alias > 0 ? row : -row, 0, -1});
    } else {
      l.where.push_back({2, storedRow[c], 0, -1});
    }
  }
  // Every parameter of the run, also those the columns leave out.
  for (const ParamValue &p : r.params)
    if (!named.count(p.name)) {
      l.names.push_back(p.name);
      l.descriptions.push_back(describe(p.description, p.unit));
      l.where.push_back({1, paramRow[p.name], 0, 0});
    }
  return l;
}

} // namespace

Expected<bool> writeMat(const SimResult &r, const std::string &path) {
  Layout l = layOut(r);
  auto file = MatFile::create(path);
  if (!file)
    return Error{file.error()};
  const size_t n = l.names.size(), nt = r.rows.size();

  std::vector<double> info; // 4 x n, column i is dataInfo(i, :)
  for (const Where &w : l.where)
    info.insert(info.end(), {double(w.block), double(w.index),
                             double(w.interpolation), double(w.extrapolation)});
  // data_1: 2 x (1 + parameters), the values at start and stop time.
  double t0 = nt ? r.rows.front()[0] : 0, tf = nt ? r.rows.back()[0] : 0;
  std::vector<double> data1{t0, tf};
  for (double v : l.paramValues)
    data1.insert(data1.end(), {v, v});
  // data_2: nt x stored, one time point per row.
  std::vector<double> data2(nt * l.stored.size());
  for (size_t j = 0; j < l.stored.size(); ++j)
    for (size_t t = 0; t < nt; ++t)
      data2[t + j * nt] = r.rows[t][l.stored[j]];

  for (auto ok :
       {file->writeStrings("Aclass", {"Atrajectory", "1.1", "", "binTrans"},
                           false),
        file->writeStrings("name", l.names, true),
        file->writeStrings("description", l.descriptions, true),
        file->writeMatrix("dataInfo", 4, n, info.data()),
        file->writeMatrix("data_1", 2, 1 + l.paramValues.size(), data1.data()),
        file->writeMatrix("data_2", nt, l.stored.size(), data2.data()),
        file->close()})
    if (!ok)
      return ok;
  return true;
}

} // namespace ldae::runtime
