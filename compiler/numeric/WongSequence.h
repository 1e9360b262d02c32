// Wong sequences of a matrix pencil (E, F) for the linear implicit system
// E x' = F x (seed 002): the consistent subspace V(E, F) and the jump
// subspace T(E, F), computed with SVD-based subspace operations. Used by the
// runtime's consistent initialization (on the model linearized at the
// current iterate) and meant to be shared by the compiler's linear-part
// analysis. Knows nothing of ldae_model.
#pragma once

#include <Eigen/Dense>

namespace ldae::numeric {

/// Orthonormal basis (columns) of the column space of `a`; singular values
/// at or below `tol` count as zero.
Eigen::MatrixXd rangeBasis(const Eigen::MatrixXd &a, double tol);
/// Orthonormal basis of the null space of `a` (n columns of `a`).
Eigen::MatrixXd nullBasis(const Eigen::MatrixXd &a, double tol);
/// Orthonormal basis of the orthogonal complement of span(s) in R^n.
Eigen::MatrixXd complementBasis(const Eigen::MatrixXd &s, Eigen::Index n,
                                double tol);
/// Basis of the preimage {x : a x in span(s)}.
Eigen::MatrixXd preimage(const Eigen::MatrixXd &a, const Eigen::MatrixXd &s,
                         double tol);
/// Basis of span(a) ∩ span(b).
Eigen::MatrixXd intersect(const Eigen::MatrixXd &a, const Eigen::MatrixXd &b,
                          double tol);
/// Whether span(a) and span(b) are the same subspace.
bool sameSubspace(const Eigen::MatrixXd &a, const Eigen::MatrixXd &b,
                  double tol);

/// The limits of both Wong sequences of (E, F).
struct WongResult {
  Eigen::MatrixXd V; ///< consistent subspace: V0 = R^n, V_{i+1} = F^{-1}(E V_i)
  Eigen::MatrixXd T; ///< jump subspace: W0 = 0, W_{i+1} = E^{-1}(F W_i)
  int stepsV = 0;    ///< iterations until V was stationary
  int stepsT = 0;    ///< smallest i with W_i = W_{i+1}: the index if regular
  bool regular = false; ///< V ⊕ T = R^n, i.e. det(sE - F) is not identically 0
};

/// Computes V(E, F) and T(E, F). `tol` is the rank tolerance relative to
/// max(|E|, |F|) (spectral norms); 0 picks 1e-10.
WongResult wongSequences(const Eigen::MatrixXd &E, const Eigen::MatrixXd &F,
                         double tol = 0);

/// Only the jump subspace T(E, F) (cheaper: one sequence).
Eigen::MatrixXd jumpSpace(const Eigen::MatrixXd &E, const Eigen::MatrixXd &F,
                          int *steps = nullptr, double tol = 0);

/// Projection of `x` onto V along T (requires a regular pencil): the x0 + t
/// (t in T) that lies in V.
Eigen::VectorXd projectAlong(const WongResult &w, const Eigen::VectorXd &x);

/// The polynomial left kernel of the pencil up to degree `degree`: the
/// w(s) = w_0 + w_1 s + ... + w_d s^d with w(s)^T (sE - F) = 0, each
/// column stacking w_0..w_d (rows(E) * (degree + 1) rows). Such a w says
/// that the equations E x' = F x + f(t) combined as sum_k w_k^T d^k/dt^k
/// leave 0 = sum_k w_k^T f^(k)(t): a condition on the inputs, which a
/// singular pencil may violate (the "conflict"). `tol` as in wongSequences.
Eigen::MatrixXd leftPolynomialKernel(const Eigen::MatrixXd &E,
                                     const Eigen::MatrixXd &F, int degree,
                                     double tol = 0);

} // namespace ldae::numeric
