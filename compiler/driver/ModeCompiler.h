// Variable-structure models (an ideal switch `if closed then v = 0 else
// i = 0`): each mode has its own structure, so its own index reduction,
// causalization and code. The run asks for a mode when an event first
// reaches it (runtime SimOptions::modeProvider); this compiles it from the
// flat model through the same pipeline and keeps it for the next time.
#pragma once

#include "codegen/Codegen.h"
#include "ir/Model.h"
#include "passes/Pipeline.h"
#include "support/Diagnostics.h"
#include "support/Expected.h"

#include <map>
#include <memory>
#include <vector>

namespace ldae::driver {

/// The first equation of `flat` that is an if-equation (the frontend
/// merges one into a residual `if c then r1 else r2`) or holds an
/// if-expression on a condition not known at compile time with a parameter
/// of value 0 in a branch, or null: only then can a mode change the
/// structure (the events pass decides).
const ir::Equation *firstVariableIf(const ir::Model &flat);

class ModeCompiler {
public:
  /// `flat` is copied before the pipeline changes the original.
  ModeCompiler(const ir::Model &flat, passes::PipelineOptions passOpts,
               codegen::CodegenOptions cgOpts, DiagnosticEngine &diags);

  /// The compiled model of mode `values`, compiled on the first call.
  Expected<const ldae_model *> model(const std::vector<double> &values);
  /// The reduced system of mode `values`, analysed on the first call.
  Expected<const ir::DaeSystem *> system(const std::vector<double> &values);
  /// Every mode a run could reach, for a program compiled ahead (--emit
  /// c): each combination of the values the mode values of `events` can
  /// take (a Boolean or a relation 0 and 1, an Integer its min to max). An
  /// error names a mode value without a finite range, or says how many
  /// more modes than kMaxModesAhead there would be.
  Expected<std::vector<std::vector<double>>>
  allModes(const ir::EventSystem &events) const;
  static constexpr size_t kMaxModesAhead = 64;
  /// How many modes were compiled, and their total compile time.
  int compiled() const { return static_cast<int>(modes_.size()); }
  double seconds() const { return seconds_; }

private:
  struct Mode {
    std::unique_ptr<ir::Model> model; // the system points into it
    passes::AnalysisResult analysis;
    std::unique_ptr<codegen::CompiledModel> code; // null until compiled
  };
  /// Mode `values`, analysed on the first call.
  Expected<Mode *> analyzed(const std::vector<double> &values);
  ir::Model flat_;
  passes::PipelineOptions passOpts_;
  codegen::CodegenOptions cgOpts_;
  DiagnosticEngine &diags_;
  std::map<std::vector<double>, Mode> modes_;
  double seconds_ = 0;
};

} // namespace ldae::driver
