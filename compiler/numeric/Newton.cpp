// Newton / Gauss–Newton iteration (see Newton.h).
#include "numeric/Newton.h"
#include "numeric/NewtonKernel.h"
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

namespace {

/// F(x) = 0 as the kernel's system: the residual's max norm judged in the
/// units of the unknowns before each step, the minimum-norm step, halved
/// (with backtracking) until the residual's 2-norm decreases.
class GaussNewtonSystem : public NewtonSystem {
public:
  GaussNewtonSystem(const ResidualFn &f, const JacobianFn &jacobian,
                    Eigen::VectorXd &x, const NewtonOptions &opts)
      : f_(f), jacobian_(jacobian), x_(x), opts_(opts) {}

  bool evaluate(int) override {
    if (!f_(x_, r_) || !r_.allFinite())
      return false;
    residualNorm = r_.size() ? r_.lpNorm<Eigen::Infinity>() : 0.0;
    return true;
  }
  bool convergedBeforeStep() override {
    double scale =
        std::max(1.0, x_.size() ? x_.lpNorm<Eigen::Infinity>() : 0);
    return residualNorm < opts_.tolerance * scale;
  }
  bool solveStep(int) override {
    bool ok = jacobian_ ? jacobian_(x_, J_)
                        : finiteDifferenceJacobian(f_, x_, r_, J_, opts_.fdStep);
    if (!ok || !J_.allFinite())
      return false;
    dx_ = minimumNormSolution(J_, -r_, opts_.rankThreshold);
    return dx_.allFinite();
  }
  TrialVerdict tryStep(double alpha) override {
    if (opts_.backtrack) {
      // Judged at a trial point: x itself moves only once accepted.
      trial_ = x_ + alpha * dx_;
      if (!(f_(trial_, rt_) && rt_.allFinite() && rt_.norm() < r_.norm()))
        return TrialVerdict::Reject;
    }
    x_ += alpha * dx_;
    return TrialVerdict::Accept;
  }
  StepVerdict afterStep(double) override { return StepVerdict::Continue; }

  double residualNorm = 0; ///< max |r_i| at the last evaluation

private:
  const ResidualFn &f_;
  const JacobianFn &jacobian_;
  Eigen::VectorXd &x_;
  const NewtonOptions &opts_;
  Eigen::VectorXd r_, dx_, trial_, rt_;
  Eigen::MatrixXd J_;
};

} // namespace

NewtonResult gaussNewton(const ResidualFn &f, const JacobianFn &jacobian,
                         Eigen::VectorXd &x, const NewtonOptions &opts) {
  GaussNewtonSystem system(f, jacobian, x, opts);
  NewtonPolicy policy;
  policy.maxIterations = opts.maxIterations;
  // Up to 30 halvings (alpha down to 2^-29); when none decreases the
  // residual, a least-squares minimum (or round-off): every further
  // iteration would repeat this one from the same point.
  policy.smallestDamping = opts.backtrack ? std::ldexp(1.0, -29) : 1.0;
  NewtonOutcome outcome = iterateNewton(system, policy);
  NewtonResult res;
  res.iterations = outcome.iterations;
  res.residualNorm = system.residualNorm;
  switch (outcome.end) {
  case NewtonEnd::Converged:
    res.status = NewtonStatus::Converged;
    break;
  case NewtonEnd::EvaluationFailed:
  case NewtonEnd::SolveFailed:
    res.status = NewtonStatus::EvaluationFailed;
    break;
  default:
    res.status = NewtonStatus::NotConverged;
  }
  return res;
}

} // namespace ldae::numeric
