// Consistent initialization by the rule of LANGUAGE.md ("Initial values",
// seed 002): fixed start values and initial equations are met exactly; the
// other start values move onto the constraints only along the jump space
// T(E, F) of the model AS WRITTEN linearized at the current iterate
// (JumpRule.h: from the reduced set's Jacobian through dummy_of /
// original_row; E = dF/dy', F = -dF/dy when the set is the model as
// written), by Newton steps in that subspace, dummy derivatives and y'
// free; where no such step exists, the nearest point in the nominal-scaled
// norm, with a warning. The same rule re-initializes the state after an
// event (reinitializeAfterEvent), the reinit targets held.
//
// For an index-1 state set whose jump space is its algebraic coordinates
// (E zero on the algebraic columns, [E_d F_a] nonsingular, no dummy whose
// constraint ties differential values) the simulator lets IDACalcIC do the
// work and does not call initializeAlongJumps. Above
// LDAE_DENSE_THRESHOLD unknowns that test and the index-1 Newton iteration
// (initializeIndexOne, when IDACalcIC fails) work on the CSC Jacobian with
// KLU: O(nnz)-ish instead of dense O(n^2) memory and O(n^3) time.
#pragma once

#include "init/InitOutcome.h"
#include "model/ModelEval.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace ldae::runtime {

/// Whether state set `set` at (t, y, y') has the plain index-1 structure
/// and the start data leave the differential values alone (no initial
/// equations, no fixed algebraic unknown), so IDACalcIC(IDA_YA_YDP_INIT)
/// is exactly the rule.
/// Above LDAE_DENSE_THRESHOLD unknowns on the CSC Jacobian (structural
/// check of E's algebraic columns, KLU without a zero pivot, reciprocal
/// condition estimate of the row-equilibrated matrix >= 1e-12); at or
/// below it with a dense rank-revealing LU.
bool isPlainIndexOne(const ModelEval &ev, int set, double t, const double *y,
                     const double *yp);
bool isPlainIndexOne(const ModelEval &ev, int set, double t, const double *y,
                     const double *yp, const InitConditions &c);

/// Whether isPlainIndexOne and initialization reports work sparsely (KLU)
/// for this model: n > LDAE_DENSE_THRESHOLD.
bool usesSparseInit(const ModelEval &ev);

/// For a state set with the plain index-1 structure: Newton iteration on
/// the algebraic values and the differential derivatives with the sparse
/// matrix [E_d D, F_a D] (KLU), the differential values kept. The same
/// iterates and convergence test as initializeAlongJumps, whose T is the
/// algebraic coordinates there, without its dense n x n matrices.
InitOutcome initializeIndexOne(const ModelEval &ev, int set, double t,
                               const std::vector<double> &y0,
                               const std::vector<double> &yp0);

/// Newton iteration along T(E, F) (see the file comment). Dense: meant for
/// small systems and high-index ones. Logs warnings to
/// `log` (may be null).
InitOutcome initializeAlongJumps(const ModelEval &ev, int set, double t,
                                 const std::vector<double> &y0,
                                 const std::vector<double> &yp0,
                                 std::ostream *log);
InitOutcome initializeAlongJumps(const ModelEval &ev, int set, double t,
                                 const std::vector<double> &y0,
                                 const std::vector<double> &yp0,
                                 const InitConditions &c, std::ostream *log);

/// The re-initialization after an event (the run loop calls it once the
/// discrete values and reinits are applied): (y, y'), the state just before
/// the event with the reinit values written into y, jumps onto the
/// consistent set of the current discrete values along T of the model as
/// written, the unknowns `held` (the targets of fired reinits) kept; where
/// holding them leaves no step along T, the nearest point with a warning.
/// Sparse (KLU) for a large set whose jump space is its algebraic
/// coordinates. Every move is logged ("re-initialization at t = 1 moved:
/// 'v2' from 1 to 4"); `jumped` counts the unknowns that moved.
InitOutcome reinitializeAfterEvent(const ModelEval &ev, int set, double t,
                                   const std::vector<double> &y,
                                   const std::vector<double> &yp,
                                   const std::vector<int> &held,
                                   std::ostream *log);

/// Logs every unknown whose value differs between `before` and `after`.
void reportMoves(const ModelEval &ev, const std::vector<double> &before,
                 const double *after, std::ostream *log);

/// The unknowns whose values differ beyond round-off (reportMoves' test).
int countMoves(const ModelEval &ev, const std::vector<double> &before,
               const double *after);

/// The derivatives of the algebraic unknowns at (t, y): the difference
/// quotient of the point solved sqrt(eps) (1 + |t|) later, the
/// differential unknowns moved along y'. False (y' unchanged) when there
/// are none or that point cannot be solved.
bool algebraicDerivatives(const ModelEval &ev, int set, double t,
                          const std::vector<double> &y,
                          std::vector<double> &yp);

/// At a root the integrator's point is its interpolating polynomial's, and
/// an algebraic unknown's polynomial is not its equation: with the
/// algebraic unknowns out of the error test (or a mode without states, an
/// ideal diode conducting: c.v = vs(t)) it is off by far more than
/// round-off (0.1 mV), and the event iteration would read that as a
/// crossing. Makes (y, y') consistent at t with the differential values of
/// state set `set` held (unchanged where that fails).
void settleAlgebraic(const ModelEval &ev, int set, double t,
                     std::vector<double> &y, std::vector<double> &yp);

} // namespace ldae::runtime
