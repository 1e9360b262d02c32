// Consistent initialization by the rule of LANGUAGE.md ("Initial values",
// seed 002): fixed start values and initial equations are met exactly; the
// other start values move onto the constraints only along the jump space
// T(E, F) of the model linearized at the current iterate (E = dF/dy',
// F = -dF/dy), by Newton steps in that subspace; where no such step exists,
// the nearest point in the nominal-scaled norm, with a warning.
//
// For an index-1 state set (E zero on the algebraic columns, [E_d F_a]
// nonsingular) T is just the algebraic coordinates; the simulator then lets
// IDACalcIC do the work and does not call initializeAlongJumps. Above
// LDAE_DENSE_THRESHOLD unknowns that test and the index-1 Newton iteration
// (initializeIndexOne, when IDACalcIC fails) work on the CSC Jacobian with
// KLU: O(nnz)-ish instead of dense O(n^2) memory and O(n^3) time.
#pragma once

#include "ModelEval.h"

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

/// Whether isPlainIndexOne and initialization reports work sparsely (KLU)
/// for this model: n > LDAE_DENSE_THRESHOLD.
bool usesSparseInit(const ModelEval &ev);

struct InitOutcome {
  bool ok = false;
  std::vector<double> y, yp;
  int jumpDim = 0;           ///< dim T at the start point (after fixing)
  int index = 0;             ///< Wong steps of T (the index of the pencil)
  bool nearestPoint = false; ///< fell back to the nominal-scaled nearest point
  double residual = 0;       ///< smallest max |residual| reached
  std::string failure;       ///< when !ok: which equations cannot be met
  int domainRow = -1;        ///< when !ok: residual row of a domain error
  std::vector<double> domainY; ///< the unknowns at that domain error
  /// False when the method does not apply to the model (see SparseInit.h);
  /// `failure` then says why.
  bool applicable = true;
  int moved = 0; ///< sparse path: differential values the conditions move
                 ///< (fixed ones not counted)
  int kept = 0;  ///< sparse path: differential values kept at their start
  int projected = 0; ///< sparse path: in minimum-norm blocks
};

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

/// Logs every unknown whose value differs between `before` and `after`.
void reportMoves(const ModelEval &ev, const std::vector<double> &before,
                 const double *after, std::ostream *log);

} // namespace ldae::runtime
