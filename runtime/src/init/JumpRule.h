// The jump directions of the initialization and of the re-initialization
// after an event (LANGUAGE.md "Initial values", seed 002): T(E, F) of the
// model AS WRITTEN, not of the reduced state set the runtime integrates.
//
// Index reduction makes a derivative der(x) an algebraic unknown (a dummy
// derivative) and adds differentiated equations; the reduced set's own
// pencil then has the algebraic coordinates as its jump space, so a tied
// differential value would be computed from the constraint instead of
// moving as an impulse moves it (two capacitors joined: v2 jumps to v1,
// charge lost). ldae_model::dummy_of / original_row give the pencil as
// written back from the reduced residual's Jacobian:
//   rows    the residual rows that are equations as written,
//   columns the unknowns that are not dummies,
//   E[r][j] = dF_r/dy'[j] + sum over dummies d of j of dF_r/dy[d],
//   F[r][j] = -dF_r/dy[j].
// The step may then move along that T (over the non-dummy unknowns) and
// freely in every dummy (a derived value, like y').
#pragma once

#include "model/ModelEval.h"

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace ldae::runtime {

/// Above this many unknowns the pencil as written is not formed (its Wong
/// sequence is dense, O(n^3) per Newton iterate): the set's own pencil
/// decides, which keeps the states (docs/runtime.md, "Initialization").
constexpr int kJumpRuleDenseLimit = 400;

/// Whether state set `set` of `m` says its pencil as written differs from
/// its own: some unknown is a dummy derivative or some row is not an
/// equation as written.
bool hasWrittenPencil(const ldae_model &m, int set);

/// The jump directions at one point, in nominal-scaled coordinates
/// (y = D u).
struct JumpDirections {
  /// Orthonormal basis (n rows): T, plus every dummy coordinate when T is
  /// the pencil as written's.
  Eigen::MatrixXd basis;
  int dim = 0;     ///< dim T (dummy coordinates not counted)
  int dummies = 0; ///< dummy coordinates in `basis`
  int index = 0;   ///< Wong steps of T (the index of its pencil if regular)
  /// Wong steps of the set's own pencil: its hidden constraints' levels.
  int setIndex = 0;
  bool written = false; ///< T is the pencil as written's
  /// Why the pencil as written was not used although the model gives one
  /// ("" when it was, or when there is none).
  std::string fallback;
};

/// T at the set's Jacobian parts E = dF/dy', Fy = dF/dy (unscaled, n x n)
/// with nominal values D.
JumpDirections jumpDirections(const ldae_model &m, int set,
                              const Eigen::MatrixXd &E,
                              const Eigen::MatrixXd &Fy,
                              const Eigen::VectorXd &D);

/// Whether the jump directions (written or not) are exactly the set's
/// algebraic coordinates: then "keep the differential values, solve the
/// rest" (IDACalcIC, the index-1 Newton) is the rule.
bool jumpsAreAlgebraic(const ldae_model &m, int set,
                       const JumpDirections &jd);

/// jumpsAreAlgebraic at (t, y, y'), true without a pencil as written or
/// above kJumpRuleDenseLimit unknowns (the states are then kept), false
/// where the Jacobian cannot be evaluated.
bool jumpRuleKeepsStates(const ModelEval &ev, int set, double t,
                         const double *y, const double *yp);

/// The geometric methods' jump directions at (t, y, y'): T of the model as
/// written (ldae_model::written_jacobian, rows equilibrated, columns in
/// nominal units), returned in the unknowns' own units (n x dim T); with
/// `held`, only its combinations that leave those unknowns (conditions:
/// fixed start values, reinit targets). Empty without the pencil, above
/// kJumpRuleDenseLimit unknowns, or where it cannot be evaluated.
Eigen::MatrixXd writtenJumpBasis(const ModelEval &ev, double t,
                                 const double *y, const double *yp,
                                 const std::vector<int> &held = {});

/// diag(nominal) of the model's unknowns (1 without nominal values).
Eigen::VectorXd nominalScale(const ldae_model &m);

} // namespace ldae::runtime
