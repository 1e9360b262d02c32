// The data half of an ldae_model: owns every array and string the C ABI
// struct points into (names, start values, patterns) and fills the struct
// from a code plan. The backends only supply the function addresses.
#pragma once

#include "codegen/CodePlan.h"
#include "ldae/model.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ldae::codegen {

class ModelTables {
public:
  /// Copies the plan's metadata; function pointers start NULL.
  explicit ModelTables(const CodePlan &plan);
  ModelTables(const ModelTables &) = delete;
  ModelTables &operator=(const ModelTables &) = delete;

  /// Sets every function pointer: `address(i)` is the machine address of
  /// plan function i (never called for absent functions).
  void setFunctions(const CodePlan &plan,
                    const std::function<uintptr_t(int)> &address);

  const ldae_model &model() const { return model_; }

private:
  /// Keeps a CSC pattern alive, points the outputs at it; returns nnz.
  int pattern(const std::vector<int> &colptr, const std::vector<int> &rowind,
              const int *&colptrOut, const int *&rowindOut);
  /// Keeps `strings` alive and returns C pointers to them.
  const char *const *names(std::vector<std::string> strings);
  /// Keeps `values` alive and returns a pointer to them (non-null even
  /// when empty).
  const int *ints(std::vector<int> values);
  /// Keeps per state set rows alive: a pointer per row, or NULL for an
  /// empty table.
  const int *const *rows(const std::vector<std::vector<int>> &table);
  /// The events block (ABI 6) of the model.
  void setEventTables(const EventPlan &events);
  /// The run-time parameters block (ABI 7) but its function.
  void setBindingTables(const CodePlan &plan);
  /// The results block (ABI 7): units, descriptions, aliases.
  void setResultTables(const CodePlan &plan);

  ldae_model model_{};
  std::vector<std::vector<std::string>> strings_;
  std::vector<std::vector<const char *>> pointers_;
  std::vector<double> startY_, startYp_, nominal_, params_, testedNominal_,
      discreteStart_, modeValues_;
  std::vector<std::vector<const int *>> rowPointers_;
  std::vector<int> fixed_;
  std::vector<std::vector<int>> ints_; // differential flags, patterns
  std::vector<ldae_state_set> sets_;
  std::vector<ldae_dynamic_set> dynamic_;
  std::vector<std::vector<double>> doubles_; // dynamic sets' start A
  std::vector<std::string> descriptions_;
  std::string name_;
};

} // namespace ldae::codegen
