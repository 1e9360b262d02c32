// The rows of a run as the simulator appends them, and takes back those of
// the time an event iteration is at (see RowSink): kept in the result, or
// handed on to a RowSink once a later time is reached, so that a long run
// streamed to a file holds only the rows of one time.
#pragma once

#include "ldae/Simulation.h"

#include <vector>

namespace ldae::runtime {

class RowLog {
public:
  /// Rows go to `res.rows`, or through them to `sink` when it is set.
  RowLog(SimResult &res, RowSink *sink) : res_(res), sink_(sink) {}

  /// Every row so far, handed on or held.
  size_t size() const { return handed_ + res_.rows.size(); }
  bool empty() const { return size() == 0; }
  /// The time of the last row (empty(): not defined).
  double lastTime() const {
    return res_.rows.empty() ? handedTime_ : res_.rows.back()[0];
  }
  /// Appends `row`; false when the sink refused a row (the run must end:
  /// SimResult::writeFailure says why).
  bool push(std::vector<double> row);
  /// Takes back the rows after the first `n`: only rows of the last time,
  /// which are still held.
  void truncate(size_t n);
  /// Hands on the rows still held (the run ended) and sets
  /// SimResult::rowCount and lastTime; false when the sink refused one.
  bool finish();

private:
  bool handOn();

  SimResult &res_;
  RowSink *sink_;
  size_t handed_ = 0;
  double handedTime_ = 0;
  bool begun_ = false;
};

} // namespace ldae::runtime
