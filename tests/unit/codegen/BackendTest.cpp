// The three backends compute the same thing: JIT == interpreter == emitted C
// (to 1e-13 relative) at random points, the interpreter == the IR's
// reference evaluator, and every Jacobian == central finite differences of
// its residual (to 1e-6), with no nonzero outside the structural pattern.
// Each model also runs cut into tiny chunks to exercise the scratch array.
#include "TestUtil.h"

#include "codegen/EventPlan.h"
#include "ir/Evaluate.h"

#include <cmath>
#include <functional>
#include <gtest/gtest.h>
#include <map>

using namespace ldae;
using namespace ldae::codegen;
using namespace ldae::codegen::testing;

namespace {

struct ModelCase {
  std::string name;
  std::function<samples::SampleSystem()> make;
  double lo, hi;   // range of random y, yp
  unsigned chunk;  // chunk size
  std::vector<double> scale = {}; // optional factor per y[i]: realistic points
};

std::ostream &operator<<(std::ostream &os, const ModelCase &c) {
  return os << c.name;
}

class Backends : public ::testing::TestWithParam<ModelCase> {
protected:
  void SetUp() override {
    s = GetParam().make();
    opts.chunkSize = GetParam().chunk;
    opts.jit = true;
    jit = compileOrDie(s.sys, opts);
    opts.jit = false;
    interp = compileOrDie(s.sys, opts);
    ASSERT_TRUE(jit && interp);
  }
  Point point(unsigned seed) {
    Point pt = randomPoint(jit->model(), seed, GetParam().lo, GetParam().hi);
    for (size_t i = 0; i < GetParam().scale.size(); ++i)
      pt.y[i] *= GetParam().scale[i];
    return pt;
  }

  samples::SampleSystem s;
  CodegenOptions opts;
  std::unique_ptr<CompiledModel> jit, interp;
};

TEST_P(Backends, JitEqualsInterpreter) {
  EXPECT_EQ(compareMetadata(jit->model(), interp->model()), "");
  for (unsigned seed = 1; seed <= 20; ++seed) {
    Point pt = point(seed);
    Evaluation a = evaluateAll(jit->model(), pt);
    Evaluation b = evaluateAll(interp->model(), pt);
    ASSERT_EQ(compareEvaluations(a, b, 1e-13), "") << "seed " << seed;
    for (int c : a.codes)
      EXPECT_EQ(c, 0) << "seed " << seed; // random points are in the domain
  }
}

/// Variable values per the layout rule for `keys`/`flags`.
std::function<double(ir::VarKey)> layoutEnv(const std::vector<ir::VarKey> &keys,
                                            const std::vector<bool> &flags,
                                            const Point &pt) {
  auto map = std::make_shared<std::map<ir::VarKey, double>>();
  for (size_t i = 0; i < keys.size(); ++i)
    (*map)[keys[i]] = pt.y[i];
  for (size_t i = 0; i < keys.size(); ++i)
    if (flags[i])
      map->emplace(ir::VarKey{keys[i].var, keys[i].order + 1}, pt.yp[i]);
  return [map](ir::VarKey k) {
    auto it = map->find(k);
    EXPECT_NE(it, map->end()) << "no slot for variable " << k.var;
    return it == map->end() ? 0.0 : it->second;
  };
}

TEST_P(Backends, InterpreterEqualsReferenceEvaluator) {
  const ir::DaeSystem &sys = s.sys;
  std::vector<ir::VarKey> baseKeys;
  for (auto &u : sys.unknowns)
    baseKeys.push_back(u.key);
  std::vector<bool> anyDiff(sys.unknowns.size(), false);
  for (auto &set : sys.stateSets)
    for (size_t i = 0; i < anyDiff.size(); ++i)
      anyDiff[i] = anyDiff[i] || set.differential[i];
  for (unsigned seed = 1; seed <= 5; ++seed) {
    Point pt = point(seed);
    ir::EvalEnv env;
    env.time = pt.t;
    env.parameter = [&](ir::ParamId p) { return pt.p[p]; };
    Evaluation got = evaluateAll(interp->model(), pt);
    auto expect = [&](const std::string &label, std::span<const ir::ExprRef> es) {
      if (es.empty())
        return;
      size_t idx = std::find(got.labels.begin(), got.labels.end(), label) -
                   got.labels.begin();
      ASSERT_LT(idx, got.labels.size()) << label;
      for (size_t i = 0; i < es.size(); ++i) {
        auto ref = ir::evaluate(es[i], env, sys.model);
        ASSERT_TRUE(bool(ref)) << ref.error();
        double v = got.arrays[idx][i];
        EXPECT_LE(std::fabs(*ref - v), 1e-13 * std::fabs(*ref))
            << label << "[" << i << "] reference " << *ref << " got " << v;
      }
    };
    for (size_t si = 0; si < sys.stateSets.size(); ++si) {
      const ir::StateSet &set = sys.stateSets[si];
      env.variable = layoutEnv(set.keys.empty() ? baseKeys : set.keys,
                               set.differential, pt);
      expect("residual " + std::to_string(si), set.residuals);
      expect("pivot " + std::to_string(si), set.pivot);
    }
    env.variable = layoutEnv(baseKeys, anyDiff, pt);
    std::vector<ir::ExprRef> outs;
    for (auto &o : sys.outputs)
      outs.push_back(o.value);
    expect("outputs", outs);
    expect("roots", sys.roots);
    expect("drift", sys.constraints);
    if (interp->model().constraints)
      expect("constraints", sys.constraints);
    expect("init_residual", sys.initialResiduals);
    EventFunctionValues events = eventFunctionValues(sys.events);
    expect("event_update", events.update);
    expect("time_events", events.timeEvents);
    expect("asserts", events.asserts);
  }
}

TEST_P(Backends, JacobianEqualsFiniteDifferences) {
  const ldae_model &m = jit->model();
  const int n = m.n;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Point pt = point(seed);
    for (int si = 0; si < m.n_state_sets; ++si) {
      const ldae_state_set &set = m.state_sets[si];
      std::vector<double> vals(set.jac_nnz + 1);
      ASSERT_EQ(set.jacobian_csc(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(),
                                 pt.cj, vals.data()),
                0);
      std::vector<double> J(size_t(n) * n, 0.0);
      for (int j = 0; j < n; ++j)
        for (int k = set.jac_colptr[j]; k < set.jac_colptr[j + 1]; ++k)
          J[size_t(j) * n + set.jac_rowind[k]] = vals[k];
      if (set.jacobian_dense) {
        std::vector<double> D(size_t(n) * n, 99.0);
        ASSERT_EQ(set.jacobian_dense(pt.t, pt.y.data(), pt.yp.data(),
                                     pt.p.data(), pt.cj, D.data()),
                  0);
        EXPECT_EQ(D, J) << "dense != scattered CSC";
      }
      // Central differences in y and y'.
      auto residual = [&](std::vector<double> &y, std::vector<double> &yp) {
        std::vector<double> r(n);
        EXPECT_EQ(set.residual(pt.t, y.data(), yp.data(), pt.p.data(), r.data()), 0);
        return r;
      };
      // Richardson-extrapolated central differences (error O(h^4)).
      auto central = [&](int j, int which, double h) {
        std::vector<double> y = pt.y, yp = pt.yp;
        std::vector<double> &v = which ? yp : y;
        double x0 = v[j];
        v[j] = x0 + h;
        auto rp = residual(y, yp);
        v[j] = x0 - h;
        auto rm = residual(y, yp);
        std::vector<double> d(n);
        for (int i = 0; i < n; ++i)
          d[i] = (rp[i] - rm[i]) / (2 * h);
        return d;
      };
      for (int j = 0; j < n; ++j) {
        std::vector<double> fd(n, 0.0);
        for (int which = 0; which < 2; ++which) {
          double h = 1e-4 * std::max(1.0, std::fabs((which ? pt.yp : pt.y)[j]));
          auto d1 = central(j, which, h), d2 = central(j, which, h / 2);
          for (int i = 0; i < n; ++i)
            fd[i] += (which ? pt.cj : 1.0) * (4 * d2[i] - d1[i]) / 3;
        }
        for (int i = 0; i < n; ++i) {
          double a = J[size_t(j) * n + i];
          EXPECT_LE(std::fabs(a - fd[i]), 1e-6 * std::max(1.0, std::fabs(a)))
              << "set " << si << " d r" << i << " / d y" << j << ": symbolic "
              << a << " vs differences " << fd[i] << " (seed " << seed << ")";
        }
      }
    }
  }
}

// The initial equations' CSC Jacobian: equal to the dense one where that
// exists, and to central differences of init_residual in y and y'.
TEST_P(Backends, InitJacobianCscEqualsDenseAndDifferences) {
  const ldae_model &m = jit->model();
  const int n = m.n, ni = m.n_init;
  ASSERT_NE(m.init_jacobian_csc, nullptr);
  EXPECT_EQ(m.init_jacobian == nullptr, n > LDAE_DENSE_THRESHOLD);
  for (unsigned seed = 1; seed <= 2; ++seed) {
    Point pt = point(seed);
    std::vector<double> jy(m.init_jac_nnz + 1), jyp(m.init_jac_nnz + 1);
    ASSERT_EQ(m.init_jacobian_csc(pt.t, pt.y.data(), pt.yp.data(),
                                  pt.p.data(), jy.data(), jyp.data()),
              0);
    std::vector<double> Sy(size_t(ni) * n, 0.0), Syp(size_t(ni) * n, 0.0);
    for (int j = 0; j < n; ++j)
      for (int k = m.init_jac_colptr[j]; k < m.init_jac_colptr[j + 1]; ++k) {
        ASSERT_LT(m.init_jac_rowind[k], ni);
        Sy[size_t(j) * ni + m.init_jac_rowind[k]] = jy[k];
        Syp[size_t(j) * ni + m.init_jac_rowind[k]] = jyp[k];
      }
    if (m.init_jacobian) {
      std::vector<double> Dy(size_t(ni) * n, 9.0), Dyp(size_t(ni) * n, 9.0);
      ASSERT_EQ(m.init_jacobian(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(),
                                Dy.data(), Dyp.data()),
                0);
      EXPECT_EQ(Dy, Sy);
      EXPECT_EQ(Dyp, Syp);
    }
    auto g = [&](std::vector<double> &y, std::vector<double> &yp) {
      std::vector<double> r(ni + 1);
      EXPECT_EQ(m.init_residual(pt.t, y.data(), yp.data(), pt.p.data(),
                                r.data()),
                0);
      return r;
    };
    for (int j = 0; j < n; ++j)
      for (int which = 0; which < 2; ++which) {
        std::vector<double> y = pt.y, yp = pt.yp;
        std::vector<double> &v = which ? yp : y;
        double h = 1e-5 * std::max(1.0, std::fabs(v[j])), x0 = v[j];
        v[j] = x0 + h;
        auto rp = g(y, yp);
        v[j] = x0 - h;
        auto rm = g(y, yp);
        const std::vector<double> &S = which ? Syp : Sy;
        for (int i = 0; i < ni; ++i) {
          double a = S[size_t(j) * ni + i], fd = (rp[i] - rm[i]) / (2 * h);
          EXPECT_LE(std::fabs(a - fd), 1e-6 * std::max(1.0, std::fabs(a)))
              << "d g" << i << " / d " << (which ? "y'" : "y") << j;
        }
      }
  }
}

TEST_P(Backends, EmittedCEqualsJit) {
  CLibrary lib(s.sys, opts);
  ASSERT_TRUE(lib.model()) << lib.error();
  EXPECT_EQ(compareMetadata(jit->model(), *lib.model()), "");
  for (unsigned seed = 1; seed <= 10; ++seed) {
    Point pt = point(seed);
    ASSERT_EQ(compareEvaluations(evaluateAll(jit->model(), pt),
                                 evaluateAll(*lib.model(), pt), 1e-13),
              "")
        << "seed " << seed;
  }
}

const ModelCase kCases[] = {
    {"robertson", samples::robertson, 0.1, 1.0, 2000, {1, 1e-4, 1}},
    {"robertson_chunked", samples::robertson, 0.1, 1.0, 3, {1, 1e-4, 1}},
    {"pendulum", samples::pendulum, -1.0, 1.0, 2000},
    {"pendulum_chunked", samples::pendulum, -1.0, 1.0, 4},
    {"pendulum_sga", [] { return samples::cartesianPendulumSga(1.0, true); },
     -1.0, 1.0, 2000},
    {"pendulum_sga_chunked",
     [] { return samples::cartesianPendulumSga(1.0, true); }, -1.0, 1.0, 3},
    {"builtins", samples::builtins, 0.1, 0.9, 2000},
    {"builtins_chunked", samples::builtins, 0.1, 0.9, 5},
    {"chain40", [] { return samples::chain(40); }, -1.0, 1.0, 2000},
    {"chain40_chunked", [] { return samples::chain(40); }, -1.0, 1.0, 16},
    // Large enough to be compiled as loops (kLoopMinStores).
    {"chain120_loops", [] { return samples::chain(120); }, -1.0, 1.0, 2000},
    {"init_chain10", [] { return samples::initChain(10); }, -1.0, 1.0, 2000},
    {"init_chain100", [] { return samples::initChain(100); }, -1.0, 1.0, 16},
    {"shuffled_chain120_loops", [] { return samples::shuffledChain(120); },
     -1.0, 1.0, 16},
    {"log_sum100_reduction", [] { return samples::logSum(100); }, 0.1, 2.0,
     2000},
    {"log_sum100_reduction_chunked", [] { return samples::logSum(100); }, 0.1,
     2.0, 7},
    {"pendulum_pencil", samples::pendulumPencil, -1.0, 1.0, 2000},
    {"bouncing_events", samples::bouncingEvents, -1.0, 1.0, 2000},
    {"bouncing_events_chunked", samples::bouncingEvents, -1.0, 1.0, 2},
};

INSTANTIATE_TEST_SUITE_P(Models, Backends, ::testing::ValuesIn(kCases),
                         [](const auto &info) { return info.param.name; });

} // namespace
