// Filling the C ABI struct from a code plan; see ModelTables.h.
#include "codegen/ModelTables.h"

namespace ldae::codegen {

const char *const *ModelTables::names(std::vector<std::string> strings) {
  strings_.push_back(std::move(strings));
  std::vector<const char *> ptrs;
  for (const std::string &s : strings_.back())
    ptrs.push_back(s.c_str());
  ptrs.push_back(nullptr); // so an empty list is still a valid pointer
  pointers_.push_back(std::move(ptrs));
  return pointers_.back().data();
}

const int *ModelTables::ints(std::vector<int> values) {
  ints_.push_back(std::move(values));
  ints_.back().push_back(0); // non-null even when empty
  return ints_.back().data();
}

const int *const *ModelTables::rows(
    const std::vector<std::vector<int>> &table) {
  if (table.empty())
    return nullptr;
  std::vector<const int *> ptrs;
  for (const std::vector<int> &row : table)
    ptrs.push_back(ints(row));
  rowPointers_.push_back(std::move(ptrs));
  return rowPointers_.back().data();
}

void ModelTables::setEventTables(const EventPlan &ev) {
  // A table whose count is 0 is NULL (a model without events has every
  // pointer of the block NULL).
  auto intTable = [&](const std::vector<int> &v) {
    return v.empty() ? nullptr : ints(v);
  };
  auto nameTable = [&](const std::vector<std::string> &v) {
    return v.empty() ? nullptr : names(v);
  };
  ldae_model &m = model_;
  m.n_discrete = int(ev.numDiscrete());
  m.discrete_names = nameTable(ev.discreteNames);
  discreteStart_ = ev.discreteStart;
  m.discrete_start = discreteStart_.empty() ? nullptr : discreteStart_.data();
  m.discrete_kind = intTable(ev.discreteKind);
  m.root_relation = intTable(ev.rootRelation);
  m.n_reinit = int(ev.reinitTarget.size());
  m.reinit_target = intTable(ev.reinitTarget);
  m.n_terminate = int(ev.terminateMessage.size());
  m.terminate_message = nameTable(ev.terminateMessage);
  m.n_time_thresholds = int(ev.thresholdRelation.size());
  m.threshold_relation = intTable(ev.thresholdRelation);
  m.n_samples = int(ev.sampleDiscrete.size());
  m.sample_discrete = intTable(ev.sampleDiscrete);
  m.n_asserts = int(ev.assertMessage.size());
  m.assert_message = nameTable(ev.assertMessage);
  m.assert_level = intTable(ev.assertLevel);
  m.assert_origin = nameTable(ev.assertOrigin);
  m.assert_value_begin = intTable(ev.assertValueBegin);
  m.n_mode = int(ev.modeDiscrete.size());
  m.mode_discrete = intTable(ev.modeDiscrete);
  modeValues_ = ev.modeValues;
  m.mode_values = modeValues_.empty() ? nullptr : modeValues_.data();
  m.dummy_of = rows(ev.dummyOf);
  m.original_row = rows(ev.originalRow);
}

void ModelTables::setBindingTables(const CodePlan &plan) {
  ldae_model &m = model_;
  m.n_bound_params = int(plan.boundParams.size());
  m.bound_params = plan.boundParams.empty() ? nullptr : ints(plan.boundParams);
  m.n_bound_starts = int(plan.boundStarts.size());
  m.bound_starts = plan.boundStarts.empty() ? nullptr : ints(plan.boundStarts);
  m.bind_passes = int(plan.bindPasses);
  bool anyStructural = false;
  for (int s : plan.structuralParams)
    anyStructural = anyStructural || s;
  m.param_structural = anyStructural ? ints(plan.structuralParams) : nullptr;
}

int ModelTables::pattern(const std::vector<int> &colptr,
                         const std::vector<int> &rowind,
                         const int *&colptrOut, const int *&rowindOut) {
  ints_.push_back(colptr);
  colptrOut = ints_.back().data();
  ints_.push_back(rowind);
  ints_.back().push_back(0); // non-null even when empty
  rowindOut = ints_.back().data();
  return int(rowind.size());
}

ModelTables::ModelTables(const CodePlan &plan) {
  // Reserve so pointers into the vectors of vectors stay valid.
  strings_.reserve(16);
  pointers_.reserve(16);
  ints_.reserve(3 * plan.stateSets.size() + 9);
  name_ = plan.name;
  startY_ = plan.startY;
  startYp_ = plan.startYp;
  nominal_ = plan.nominal;
  params_ = plan.paramValues;
  fixed_ = plan.fixed;

  ldae_model &m = model_;
  m.abi_version = LDAE_ABI_VERSION;
  m.name = name_.c_str();
  m.n = plan.n;
  m.var_names = names(plan.varNames);
  m.start_y = startY_.data();
  m.start_yp = startYp_.data();
  m.nominal = nominal_.data();
  m.fixed = fixed_.data();
  m.n_params = params_.size();
  m.param_names = names(plan.paramNames);
  m.param_values = params_.data();
  m.n_init = plan.nInit;
  m.init_jac_nnz =
      pattern(plan.initColptr, plan.initRowind, m.init_jac_colptr,
              m.init_jac_rowind);
  m.n_roots = plan.nRoots;
  m.n_outputs = plan.nOutputs;
  m.output_names = names(plan.outputNames);
  m.n_drift = plan.nDrift;
  m.n_ode = plan.nOde;
  m.n_constraints = plan.nConstraints;
  m.project_constraints = plan.projectConstraints ? 1 : 0;
  m.residual_origin =
      plan.residualOrigin.empty() ? nullptr : names(plan.residualOrigin);
  m.output_origin =
      plan.outputOrigin.empty() ? nullptr : names(plan.outputOrigin);
  m.explicit_ode = plan.explicitOde ? 1 : 0;
  m.algebraic_error_test = plan.algebraicErrorTest ? 1 : 0;
  testedNominal_ = plan.testedNominal;
  m.n_tested = static_cast<int>(plan.testedNominal.size());
  m.tested_nominal = testedNominal_.data();
  if (m.n_tested > 0)
    m.tested_jac_nnz = pattern(plan.testedColptr, plan.testedRowind,
                               m.tested_jac_colptr, m.tested_jac_rowind);
  m.start_time = plan.startTime;
  m.stop_time = plan.stopTime;
  m.tolerance = plan.tolerance;
  m.interval = plan.interval;

  descriptions_.reserve(plan.stateSets.size());
  for (const StateSetPlan &sp : plan.stateSets) {
    ldae_state_set s{};
    ints_.push_back(sp.isDifferential);
    s.is_differential = ints_.back().data();
    s.jac_nnz = pattern(sp.colptr, sp.rowind, s.jac_colptr, s.jac_rowind);
    s.pivot_size = sp.pivotSize;
    descriptions_.push_back(sp.description);
    s.description = descriptions_.back().c_str();
    sets_.push_back(s);
  }
  m.n_state_sets = sets_.size();
  m.state_sets = sets_.data();
  for (const DynamicSetPlan &dp : plan.dynamicSets) {
    ldae_dynamic_set d{};
    d.rows = dp.rows;
    d.forced = dp.forced;
    d.candidates = dp.candidates;
    d.param = dp.param;
    doubles_.push_back(dp.start);
    d.start = doubles_.back().data();
    d.state_slots = ints(dp.stateSlots);
    d.names = names(dp.names);
    dynamic_.push_back(d);
  }
  m.n_dynamic_sets = static_cast<int>(dynamic_.size());
  m.dynamic_sets = dynamic_.empty() ? nullptr : dynamic_.data();
  m.n_selection = static_cast<int>(plan.selectionCount);
  m.n_written = static_cast<int>(plan.nWritten);
  setEventTables(plan.events);
  setBindingTables(plan);
  setResultTables(plan);
}

void ModelTables::setResultTables(const CodePlan &plan) {
  ldae_model &m = model_;
  m.output_unit = names(plan.outputUnit);
  m.output_description = names(plan.outputDescription);
  m.output_alias = ints(plan.outputAlias);
  m.param_unit = names(plan.paramUnit);
  m.param_description = names(plan.paramDescription);
}

void ModelTables::setFunctions(const CodePlan &plan,
                               const std::function<uintptr_t(int)> &address) {
  auto fn = [&](int index, auto &slot) {
    slot = index < 0 ? nullptr
                     : reinterpret_cast<std::remove_reference_t<decltype(slot)>>(
                           address(index));
  };
  for (size_t i = 0; i < sets_.size(); ++i) {
    const StateSetPlan &sp = plan.stateSets[i];
    fn(sp.residual, sets_[i].residual);
    fn(sp.jacobianDense, sets_[i].jacobian_dense);
    fn(sp.jacobianCsc, sets_[i].jacobian_csc);
    fn(sp.pivot, sets_[i].pivot);
  }
  for (size_t i = 0; i < dynamic_.size(); ++i) {
    fn(plan.dynamicSets[i].jacobian, dynamic_[i].jacobian);
    fn(plan.dynamicSets[i].values, dynamic_[i].values);
  }
  fn(plan.initResidual, model_.init_residual);
  fn(plan.initJacobian, model_.init_jacobian);
  fn(plan.initJacobianCsc, model_.init_jacobian_csc);
  fn(plan.writtenResidual, model_.written_residual);
  fn(plan.writtenJacobian, model_.written_jacobian);
  fn(plan.roots, model_.roots);
  fn(plan.outputs, model_.outputs);
  fn(plan.drift, model_.drift);
  fn(plan.tested, model_.tested);
  fn(plan.testedJacobianCsc, model_.tested_jacobian_csc);
  fn(plan.constraints, model_.constraints);
  fn(plan.constraintJacobian, model_.constraint_jacobian);
  fn(plan.events.update, model_.event_update);
  fn(plan.events.timeEvents, model_.time_events);
  fn(plan.events.asserts, model_.asserts);
  fn(plan.bind, model_.bind);
}

} // namespace ldae::codegen
