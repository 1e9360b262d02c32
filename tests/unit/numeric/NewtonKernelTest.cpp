// The Newton kernel's order of operations, damping and ends on scalar
// systems whose iterates are known by hand.
#include "numeric/NewtonKernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace ldae::numeric;

namespace {

/// atan(x) = 0 by Newton's method, the step accepted when |r| decreases
/// (with `damped`): full steps from |x| > 1.39 diverge.
class Atan : public NewtonSystem {
public:
  Atan(double x, bool damped) : x(x), damped_(damped) {}

  bool evaluate(int) override {
    r_ = std::atan(x);
    calls += "e";
    return std::isfinite(r_);
  }
  bool convergedBeforeStep() override { return std::fabs(r_) < 1e-12; }
  bool solveStep(int) override {
    calls += "s";
    from_ = x;
    dx_ = -r_ * (1 + x * x);
    return true;
  }
  TrialVerdict tryStep(double alpha) override {
    calls += "t";
    x = from_ + alpha * dx_;
    if (!damped_ || std::fabs(std::atan(x)) < std::fabs(r_))
      return TrialVerdict::Accept;
    return TrialVerdict::Reject;
  }
  void restore() override { x = from_; }
  StepVerdict afterStep(double alpha) override {
    calls += "a";
    alphas.push_back(alpha);
    return StepVerdict::Continue;
  }

  double x;
  std::string calls;
  std::vector<double> alphas;

private:
  bool damped_;
  double r_ = 0, from_ = 0, dx_ = 0;
};

} // namespace

TEST(NewtonKernel, FullStepsConvergeNearTheRoot) {
  Atan s(0.5, false);
  NewtonOutcome out = iterateNewton(s, {});
  ASSERT_EQ(out.end, NewtonEnd::Converged);
  EXPECT_NEAR(s.x, 0, 1e-12);
  // Cubic convergence of Newton on atan from 0.5: a few steps, and the
  // calls in the kernel's order, the last evaluation converged.
  EXPECT_EQ(s.calls.substr(0, 8), "estaesta");
  EXPECT_EQ(s.calls.back(), 'e');
  EXPECT_EQ(out.iterations, int(s.alphas.size()));
}

TEST(NewtonKernel, FullStepsDivergeFarFromTheRoot) {
  Atan s(2, false);
  NewtonPolicy policy;
  policy.maxIterations = 5;
  NewtonOutcome out = iterateNewton(s, policy);
  EXPECT_NE(out.end, NewtonEnd::Converged);
  EXPECT_GT(std::fabs(s.x), 2);
}

TEST(NewtonKernel, HalvedStepsConvergeFarFromTheRoot) {
  Atan s(2, true);
  NewtonPolicy policy;
  policy.smallestDamping = 1e-3;
  NewtonOutcome out = iterateNewton(s, policy);
  ASSERT_EQ(out.end, NewtonEnd::Converged);
  EXPECT_NEAR(s.x, 0, 1e-12);
  // The first step from 2 overshoots to -5.3: halved.
  ASSERT_FALSE(s.alphas.empty());
  EXPECT_LT(s.alphas.front(), 1);
  EXPECT_EQ(s.alphas.back(), 1);
}

namespace {
/// A step that is never accepted.
class Rejecting : public NewtonSystem {
public:
  bool evaluate(int) override { return true; }
  bool solveStep(int) override { return true; }
  TrialVerdict tryStep(double alpha) override {
    last = alpha;
    ++trials;
    return TrialVerdict::Reject;
  }
  void restore() override { restored = true; }
  StepVerdict afterStep(double) override { return StepVerdict::Continue; }
  double last = 0;
  int trials = 0;
  bool restored = false;
};
} // namespace

TEST(NewtonKernel, StallsWhenNoDampingIsAccepted) {
  Rejecting s;
  NewtonPolicy policy;
  policy.smallestDamping = std::ldexp(1.0, -29);
  NewtonOutcome out = iterateNewton(s, policy);
  EXPECT_EQ(out.end, NewtonEnd::Stalled);
  EXPECT_EQ(out.iterations, 1);
  EXPECT_EQ(s.trials, 30);
  EXPECT_EQ(s.last, std::ldexp(1.0, -29));
  EXPECT_TRUE(s.restored);
}

TEST(NewtonKernel, FullStepsOnlyStallAtTheFirstRejection) {
  Rejecting s;
  NewtonOutcome out = iterateNewton(s, {});
  EXPECT_EQ(out.end, NewtonEnd::Stalled);
  EXPECT_EQ(s.trials, 1);
}

namespace {
/// Ends as told at iteration `at`.
class Ending : public NewtonSystem {
public:
  enum class How { Evaluate, Solve, Trial, Stop } how;
  int at;
  Ending(How how, int at) : how(how), at(at) {}
  bool evaluate(int it) override { return !(how == How::Evaluate && it == at); }
  bool solveStep(int it) override {
    it_ = it;
    return !(how == How::Solve && it == at);
  }
  TrialVerdict tryStep(double) override {
    return how == How::Trial && it_ == at ? TrialVerdict::Fail
                                          : TrialVerdict::Accept;
  }
  StepVerdict afterStep(double) override {
    return how == How::Stop && it_ == at ? StepVerdict::Stop
                                         : StepVerdict::Continue;
  }

private:
  int it_ = 0;
};
} // namespace

TEST(NewtonKernel, EachEndAtItsIteration) {
  using How = Ending::How;
  struct Case {
    How how;
    int at;
    NewtonEnd end;
    int iterations;
  };
  NewtonPolicy policy;
  policy.maxIterations = 10;
  for (Case c : {Case{How::Evaluate, 3, NewtonEnd::EvaluationFailed, 3},
                 Case{How::Solve, 3, NewtonEnd::SolveFailed, 3},
                 Case{How::Trial, 3, NewtonEnd::EvaluationFailed, 3},
                 Case{How::Stop, 3, NewtonEnd::Stopped, 4},
                 Case{How::Stop, 99, NewtonEnd::IterationLimit, 10}}) {
    Ending system(c.how, c.at);
    NewtonOutcome out = iterateNewton(system, policy);
    EXPECT_EQ(out.end, c.end) << int(c.how);
    EXPECT_EQ(out.iterations, c.iterations) << int(c.how);
  }
}
