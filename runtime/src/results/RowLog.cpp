// The rows of a run, held or handed on (see RowLog.h).
#include "results/RowLog.h"

namespace ldae::runtime {

bool RowLog::handOn() {
  if (!sink_ || res_.rows.empty() || !res_.writeFailure.empty())
    return res_.writeFailure.empty();
  if (!begun_) {
    begun_ = true;
    if (auto ok = sink_->begin(res_); !ok) {
      res_.writeFailure = ok.error();
      return false;
    }
  }
  for (const std::vector<double> &row : res_.rows)
    if (auto ok = sink_->row(row); !ok) {
      res_.writeFailure = ok.error();
      return false;
    }
  handed_ += res_.rows.size();
  handedTime_ = res_.rows.back()[0];
  res_.rows.clear();
  return true;
}

bool RowLog::push(std::vector<double> row) {
  bool ok = true;
  if (sink_ && !res_.rows.empty() && row[0] > res_.rows.back()[0])
    ok = handOn();
  res_.rows.push_back(std::move(row));
  return ok;
}

void RowLog::truncate(size_t n) {
  res_.rows.resize(n > handed_ ? n - handed_ : 0);
}

bool RowLog::finish() {
  bool ok = handOn();
  res_.rowCount = size();
  res_.lastTime = empty() ? 0 : lastTime();
  return ok;
}

} // namespace ldae::runtime
