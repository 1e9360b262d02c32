// Newton / Gauss–Newton iteration (see Newton.h).
#include "numeric/Newton.h"
#include "numeric/Rank.h"

#include <algorithm>
#include <cmath>

namespace ldae::numeric {

bool finiteDifferenceJacobian(const ResidualFn &f, const Eigen::VectorXd &x,
                              const Eigen::VectorXd &r0, Eigen::MatrixXd &J,
                              double relStep) {
  Eigen::VectorXd xp = x, r1(r0.size());
  J.resize(r0.size(), x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    double h = relStep * std::max(1.0, std::fabs(x[k]));
    xp[k] = x[k] + h;
    bool ok = f(xp, r1);
    xp[k] = x[k];
    if (!ok)
      return false;
    J.col(k) = (r1 - r0) / h;
  }
  return true;
}

NewtonResult gaussNewton(const ResidualFn &f, const JacobianFn &jacobian,
                         Eigen::VectorXd &x, const NewtonOptions &opts) {
  NewtonResult res;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  for (int it = 0; it < opts.maxIterations; ++it) {
    res.iterations = it;
    if (!f(x, r) || !r.allFinite()) {
      res.status = NewtonStatus::EvaluationFailed;
      return res;
    }
    res.residualNorm = r.size() ? r.lpNorm<Eigen::Infinity>() : 0.0;
    double scale = std::max(1.0, x.size() ? x.lpNorm<Eigen::Infinity>() : 0);
    if (res.residualNorm < opts.tolerance * scale) {
      res.status = NewtonStatus::Converged;
      return res;
    }
    bool ok = jacobian ? jacobian(x, J)
                       : finiteDifferenceJacobian(f, x, r, J, opts.fdStep);
    if (!ok || !J.allFinite()) {
      res.status = NewtonStatus::EvaluationFailed;
      return res;
    }
    Eigen::VectorXd dx = minimumNormSolution(J, -r, opts.rankThreshold);
    if (!dx.allFinite()) {
      res.status = NewtonStatus::EvaluationFailed;
      return res;
    }
    if (opts.backtrack) {
      const double before = r.norm();
      Eigen::VectorXd trial, rt;
      bool decreased = false;
      for (int half = 0; half < 30 && !decreased; ++half) {
        trial = x + dx;
        decreased = f(trial, rt) && rt.allFinite() && rt.norm() < before;
        if (!decreased)
          dx *= 0.5;
      }
      // No step along the Gauss–Newton direction decreases the residual:
      // a least-squares minimum (or round-off). Every further iteration
      // would repeat this one from the same point.
      if (!decreased) {
        res.iterations = it + 1;
        res.status = NewtonStatus::NotConverged;
        return res;
      }
    }
    x += dx;
  }
  res.iterations = opts.maxIterations;
  res.status = NewtonStatus::NotConverged;
  return res;
}

} // namespace ldae::numeric
