// The jump rule's tables (DaeSystem::dummyOf / originalRow, ldae_model
// dummy_of / original_row): from them the runtime rebuilds the pencil of
// the model AS WRITTEN from the reduced residual's Jacobian and
// (re-)initializes along its T(E, F) (LANGUAGE.md "Initial values", seed
// 002; runtime/src/init/JumpRule.h, docs/events.md).
#pragma once

#include "ir/DaeSystem.h"
#include "passes/PassContext.h"
#include "passes/Results.h"

#include <vector>

namespace ldae::passes {

/// Fills sys.dummyOf and sys.originalRow from build-system's own inputs
/// (called at its end, before any later pass reorders the system):
///  - slot u of order k >= 1 of an unknown is, in a state set whose choice
///    makes order k a dummy, the derivative of the slot of order k - 1;
///  - a row is an equation as written when it is one of the model's
///    equations not differentiated (times = 0) or a link row `der(slot) -
///    next slot` (the first-order form of a model written with
///    der(der(x)): without it such an x would look algebraic).
/// Left empty where the tables would say nothing (no dummy, every row as
/// written), and where a later pass rewrites the rows (causalize: its
/// substitutions through differentiated rows change which column an
/// equation's derivative is on) or may drop some (prune, with requested
/// outputs): the runtime then uses the reduced set's own pencil. Where
/// jumps matter (PassContext::jumpsMatter: the alias pass kept aliases
/// whose values may differ) those passes stand aside and the tables are
/// filled.
void fillJumpPencil(const PassContext &pc, const MatchingResult &mr,
                    const IndexReduction &red, const DummyChoices &dc,
                    ir::DaeSystem &sys);

/// The tables after a pass kept only some unknowns (newIndex[old] = new
/// index or -1) and, per state set, only the rows keptRows[set] (old
/// indices, in their new order) without rewriting them (prune). False,
/// and the tables cleared, when a kept dummy's variable was dropped: the
/// pencil as written is then not in the system any more.
bool restrictJumpPencil(ir::DaeSystem &sys, const std::vector<int> &newIndex,
                        const std::vector<std::vector<int>> &keptRows);

} // namespace ldae::passes
