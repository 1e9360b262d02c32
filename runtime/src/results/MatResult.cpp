// The OpenModelica/Dymola result layout on a MatFile (see MatResult.h).
// Written from OpenModelica's user's guide, "The MATv4 Result File
// Format", with the orientation its reader (read_matlab4.c) takes for
// "binTrans": `name` and `description` hold one variable per column,
// dataInfo is 4 x n, data_1 is (parameters x 2) with time as row 1, and
// data_2 is (variables x time points), so that each time point is one
// column, contiguous on disk and appended as the run produces it.
#include "results/MatResult.h"
#include "results/MatFile.h"

#include <optional>
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

/// The .mat file written as the run goes: the variables' names and info
/// once the columns are known, data_1 with the first row's time, a column
/// of data_2 per row, the stop time and data_2's column count at the end.
class MatResultFile : public ResultFile {
public:
  explicit MatResultFile(std::string path) : path_(std::move(path)) {}

  Expected<bool> begin(const SimResult &header) override {
    layout_ = layOut(header);
    return true;
  }

  Expected<bool> row(const std::vector<double> &row) override {
    if (!file_)
      if (auto ok = start(row[0]); !ok)
        return ok;
    for (size_t j = 0; j < layout_.stored.size(); ++j)
      column_[j] = row[layout_.stored[j]];
    lastTime_ = row[0];
    return file_->appendColumn(column_.data());
  }

  Expected<bool> finish(const SimResult &result) override {
    if (!file_) {
      if (layout_.names.empty())
        layout_ = layOut(result);
      if (auto ok = start(0); !ok)
        return ok;
    }
    auto stop = file_->overwriteLast(0, 1, lastTime_);
    auto closed = file_->close();
    return !closed ? closed : stop;
  }

private:
  /// Everything before data_2's columns; data_1's stop time is `t0` until
  /// finish() knows it.
  Expected<bool> start(double t0) {
    auto file = MatFile::create(path_);
    if (!file)
      return Error{file.error()};
    file_.emplace(std::move(*file));
    lastTime_ = t0;
    const Layout &l = layout_;
    const size_t n = l.names.size(), np = l.paramValues.size();
    std::vector<double> info; // 4 x n, column i is dataInfo(i, :)
    for (const Where &w : l.where)
      info.insert(info.end(), {double(w.block), double(w.index),
                               double(w.interpolation),
                               double(w.extrapolation)});
    // data_1: (1 + parameters) x 2, start values in the first column,
    // stop values in the second; row 1 is time.
    std::vector<double> data1;
    for (int side = 0; side < 2; ++side) {
      data1.push_back(t0);
      data1.insert(data1.end(), l.paramValues.begin(), l.paramValues.end());
    }
    column_.assign(l.stored.size(), 0.0);
    for (auto ok :
         {file_->writeStrings("Aclass", {"Atrajectory", "1.1", "", "binTrans"},
                              false),
          file_->writeStrings("name", l.names, true),
          file_->writeStrings("description", l.descriptions, true),
          file_->writeMatrix("dataInfo", 4, n, info.data()),
          file_->writeMatrix("data_1", 1 + np, 2, data1.data()),
          file_->beginColumns("data_2", l.stored.size())})
      if (!ok)
        return ok;
    return true;
  }

  std::string path_;
  Layout layout_;
  std::optional<MatFile> file_;
  std::vector<double> column_;
  double lastTime_ = 0;
};

} // namespace

std::unique_ptr<ResultFile> matResultFile(const std::string &path) {
  return std::make_unique<MatResultFile>(path);
}

} // namespace ldae::runtime
