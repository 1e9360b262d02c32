// The rows of one run for numpy: a RowSink (SimOptions::rowSink) that
// keeps them in one row-major block as the run produces them, so that the
// array numpy gets is a view of that block (kept alive by the array),
// without a copy per element or per row.
#pragma once

#include "ldae/Simulation.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace ldae::python {

class RowTable : public runtime::RowSink {
public:
  Expected<bool> begin(const runtime::SimResult &header) override {
    columns_ = header.columns.size();
    return true;
  }

  /// A row shorter than the header is completed with NaN, a longer one
  /// cut (the table is rectangular).
  Expected<bool> row(const std::vector<double> &row) override {
    size_t n = std::min(row.size(), columns_);
    values_->insert(values_->end(), row.begin(), row.begin() + n);
    values_->insert(values_->end(), columns_ - n, NAN);
    return true;
  }

  size_t rows() const { return columns_ ? values_->size() / columns_ : 0; }
  size_t columns() const { return columns_; }
  /// The block, row-major; shared with the arrays that view it.
  const std::shared_ptr<std::vector<double>> &values() const {
    return values_;
  }

  /// The rows one vector each, as SimResult::rows holds them (for the
  /// result writers).
  std::vector<std::vector<double>> rowVectors() const {
    std::vector<std::vector<double>> out;
    for (size_t i = 0; i < rows(); ++i)
      out.emplace_back(values_->begin() + i * columns_,
                       values_->begin() + (i + 1) * columns_);
    return out;
  }

private:
  size_t columns_ = 0;
  std::shared_ptr<std::vector<double>> values_ =
      std::make_shared<std::vector<double>>();
};

} // namespace ldae::python
