// The create function of every pass in Passes.def (each defined at the
// bottom of its own file), their options, and the pipeline of each method.
// Internal to compiler/passes; the public face is Pipeline.h.
#pragma once

#include "passes/Method.h"
#include "passes/Pass.h"

#include <memory>
#include <vector>

namespace ldae::passes {

struct PantelidesOptions {
  /// false (`--method raw`): Pantelides still runs for the index report
  /// (structural index, the equations it would differentiate), but what it
  /// hands on is the model as written: its equations, no derivatives, every
  /// unknown at its highest order in the model.
  bool reduce = true;
};

struct BltOptions {
  /// The unreduced system of `--method raw` is singular whenever the
  /// model's index exceeds one: that is what raw is for, not an error.
  bool allowSingular = false;
};

std::unique_ptr<Pass> createEventsPass();
std::unique_ptr<Pass> createLinearPencilPass();
std::unique_ptr<Pass> createAliasEliminationPass();
std::unique_ptr<Pass> createMatchingPass();
std::unique_ptr<Pass> createFormalIndexPass();
std::unique_ptr<Pass> createDmDiagnosisPass();
/// `always`: run whatever the model's size (the sga and ode methods);
/// otherwise only up to kSgaCrossCheckLimit coordinates.
std::unique_ptr<Pass> createSgaPass(bool always = false);
std::unique_ptr<Pass> createSgaSystemPass();
std::unique_ptr<Pass> createSgaCheckPass();
std::unique_ptr<Pass> createPantelidesPass(const PantelidesOptions &opts = {});
/// Pryce's structural index of `m` as written (before alias elimination,
/// which can hide differentiations: seed 000's sliding control, 3 as
/// written, 0 after); none when Pantelides fails on it.
std::optional<int> structuralIndexAsWritten(ir::Model &m);
std::unique_ptr<Pass> createDummyDerivativesPass();
std::unique_ptr<Pass> createBuildSystemPass();
std::unique_ptr<Pass> createBltPass(const BltOptions &opts = {});
std::unique_ptr<Pass> createPrunePass();
std::unique_ptr<Pass> createCausalizePass();
std::unique_ptr<Pass> createInitializationPass();

struct BltResult;

/// The BLT order of every state set of `sys` ("blt"; "prune" orders the
/// pruned system again). Unless `allowSingular`, a residual that cannot be
/// matched is diagnosed and the result is false.
bool bltOrder(PassContext &ctx, const ir::DaeSystem &sys, bool allowSingular,
              BltResult &out);

using PassPipeline = std::vector<std::unique_ptr<Pass>>;

/// The passes `method` runs, in order (a subsequence of Passes.def).
PassPipeline pipelineFor(Method method);

} // namespace ldae::passes
