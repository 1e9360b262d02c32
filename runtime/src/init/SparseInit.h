// Sparse consistent initialization of large index-1 models with initial
// equations or fixed algebraic values (docs/runtime.md, "Sparse
// initialization"): no matrix of the model's size is ever dense.
//
// The unknowns are, per model unknown j, v_j (y'_j when j is differential,
// y_j when algebraic) and, for differential j, x_j = y_j. The rows are the
// residuals F, the initial equations G, one row y_j = start_j per fixed
// unknown, and "keep the start value" rows x_j = start_j for the
// differential values the other rows leave free (at an event: the reinit
// targets instead of the fixed values, no G). Which ones are free is
// decided structurally: a maximum matching of the rows over the v columns
// first, extended over the x columns (so as few differential values move as
// the conditions allow, ties broken by index); every x column left
// unmatched gets a keep row. The square system is solved by Newton's method
// with KLU, O(nnz) per iteration.
//
// Where the choice of which differential values move is not unique (an
// initial equation ties several of them: an alternating path joins a moved
// x column to a kept one), the rule of LANGUAGE.md asks for the smallest
// move: those keep rows are dropped and the step minimizes the
// nominal-scaled distance of that block's differential values from their
// start values subject to the other rows (a sparse KKT system, KLU).
#pragma once

#include "init/InitOutcome.h"
#include "model/ModelEval.h"

namespace ldae::runtime {

/// The sparse initialization of state set `set` from (y0, yp0). When the
/// model does not have the form it handles (E not zero on the algebraic
/// columns, a structurally singular or over-determined system, a system
/// numerically singular at the start values, no CSC Jacobian of the initial
/// equations) the outcome has applicable = false and the failure says why;
/// the caller then falls back to the dense path.
InitOutcome initializeSparse(const ModelEval &ev, int set, double t,
                             const std::vector<double> &y0,
                             const std::vector<double> &yp0);
/// The same with conditions other than the start's (an event's reinit
/// targets held, no initial equations). Not applicable either where the
/// jump rule moves differential values (T of the model as written is not
/// the set's algebraic coordinates: JumpRule.h).
InitOutcome initializeSparse(const ModelEval &ev, int set, double t,
                             const std::vector<double> &y0,
                             const std::vector<double> &yp0,
                             const InitConditions &c);

} // namespace ldae::runtime
