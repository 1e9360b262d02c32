// The events block of the C ABI (ABI 6) from a hand-built system
// (samples::bouncingEvents): the LLVM JIT, the interpreter and the emitted C
// fill the same tables and compute the same event update, time events,
// asserts and roots, the values worked out by hand; residuals read the
// frozen discrete values from p; a model without events has the block
// NULL; tables that do not fit the system are refused.
#include "TestUtil.h"

#include "codegen/Interpreter.h"
#include "codegen/PlanLowering.h"

#include <gtest/gtest.h>

using namespace ldae;
using namespace ldae::codegen;
using namespace ldae::codegen::testing;

namespace {

const char *kBackend[] = {"jit", "interpreter", "emitted C"};

/// Runs `check` on the model of each backend of `s` (the JIT, the
/// interpreter, the emitted C), traced with its name.
template <typename Check>
void onEachBackend(samples::SampleSystem s, Check check) {
  CodegenOptions opts;
  opts.jit = true;
  auto jit = compileOrDie(s.sys, opts);
  opts.jit = false;
  auto interp = compileOrDie(s.sys, opts);
  CLibrary c(s.sys, opts);
  ASSERT_TRUE(jit && interp);
  ASSERT_TRUE(c.model()) << c.error();
  const ldae_model *models[] = {&jit->model(), &interp->model(), c.model()};
  for (size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(kBackend[i]);
    check(*models[i]);
  }
}

// bouncingEvents: 6 parameters, 7 discrete values.
constexpr int kParams = 6, kDiscrete = 7;
enum Slot { Ground, When, Late, On, Sample, Count, Initial };

struct EventPoint {
  double t, h, v;
  std::vector<double> current, pre; // kDiscrete each
};

Point at(const ldae_model &m, const EventPoint &e) {
  Point pt;
  pt.t = e.t;
  pt.y = {e.h, e.v};
  pt.yp = {e.v, -9.81};
  pt.p = parameterVector(m);
  for (int k = 0; k < kDiscrete; ++k) {
    pt.p[kParams + k] = e.current[k];
    pt.p[kParams + kDiscrete + k] = e.pre[k];
  }
  return pt;
}

/// Calls an outputs-type function at `pt`; the return code in `rc`.
std::vector<double> call(ldae_outputs_fn f, size_t size, const Point &pt,
                         int &rc) {
  std::vector<double> out(size, -1);
  rc = f(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(), out.data());
  return out;
}

TEST(Events, TablesMatchTheSystem) {
  onEachBackend(samples::bouncingEvents(), [&](const ldae_model &m) {
    EXPECT_EQ(m.abi_version, LDAE_ABI_VERSION);
    EXPECT_EQ(m.n_params, kParams); // the user's parameters only
    ASSERT_EQ(m.n_discrete, kDiscrete);
    const char *names[] = {"h <= 0",         "when h <= 0", "time >= t0", "on",
                           "sample(ts, ti)", "count",       "initial()"};
    const int kinds[] = {LDAE_DISCRETE_RELATION, LDAE_DISCRETE_WHEN,
                         LDAE_DISCRETE_RELATION, LDAE_DISCRETE_VARIABLE,
                         LDAE_DISCRETE_SAMPLE,   LDAE_DISCRETE_VARIABLE,
                         LDAE_DISCRETE_INITIAL};
    for (int k = 0; k < kDiscrete; ++k) {
      EXPECT_STREQ(m.discrete_names[k], names[k]);
      EXPECT_EQ(m.discrete_kind[k], kinds[k]);
      EXPECT_EQ(m.discrete_start[k], k == Initial ? 1 : 0);
    }
    ASSERT_EQ(m.n_roots, 1);
    EXPECT_EQ(m.root_relation[0], Ground);
    ASSERT_EQ(m.n_reinit, 1);
    EXPECT_EQ(m.reinit_target[0], 1); // v
    ASSERT_EQ(m.n_terminate, 1);
    EXPECT_STREQ(m.terminate_message[0], "too high");
    ASSERT_EQ(m.n_time_thresholds, 1);
    EXPECT_EQ(m.threshold_relation[0], Late);
    ASSERT_EQ(m.n_samples, 1);
    EXPECT_EQ(m.sample_discrete[0], Sample);
    ASSERT_EQ(m.n_asserts, 2);
    EXPECT_STREQ(m.assert_message[0], "below ground");
    EXPECT_STREQ(m.assert_message[1], "too fast");
    EXPECT_EQ(m.assert_level[0], 0);
    EXPECT_EQ(m.assert_level[1], 1);
    EXPECT_STREQ(m.assert_origin[0], ""); // no source manager
    ASSERT_EQ(m.n_mode, 1);
    EXPECT_EQ(m.mode_discrete[0], On);
    EXPECT_EQ(m.mode_values[0], 0);
    ASSERT_TRUE(m.dummy_of && m.original_row);
    EXPECT_EQ(m.dummy_of[0][0], -1);
    EXPECT_EQ(m.dummy_of[0][1], -1);
    EXPECT_EQ(m.original_row[0][1], 1);
    EXPECT_TRUE(m.event_update && m.time_events && m.asserts);
  });
}

TEST(Events, PencilOfTheModelAsWritten) {
  const int dummyA[] = {-1, -1, -1, -1, -1, 1, 3};
  const int dummyB[] = {-1, -1, -1, -1, -1, 0, 2};
  onEachBackend(samples::pendulumPencil(), [&](const ldae_model &m) {
    ASSERT_EQ(m.n_state_sets, 2);
    ASSERT_TRUE(m.dummy_of && m.original_row);
    for (int r = 0; r < m.n; ++r) {
      EXPECT_EQ(m.dummy_of[0][r], dummyA[r]);
      EXPECT_EQ(m.dummy_of[1][r], dummyB[r]);
      for (int s = 0; s < 2; ++s)
        EXPECT_EQ(m.original_row[s][r], r < 5 ? 1 : 0);
    }
    // No discrete state: the rest of the block stays NULL.
    EXPECT_EQ(m.n_discrete, 0);
    EXPECT_EQ(m.event_update, nullptr);
  });
}

TEST(Events, WithoutEventsTheBlockIsNull) {
  onEachBackend(samples::robertson(), [&](const ldae_model &m) {
    EXPECT_EQ(m.n_roots, 1); // a plain root keeps working
    EXPECT_TRUE(m.n_discrete == 0 && m.n_reinit == 0 && m.n_terminate == 0 &&
                m.n_time_thresholds == 0 && m.n_samples == 0 &&
                m.n_asserts == 0 && m.n_mode == 0);
    const void *pointers[] = {
        m.discrete_names,     m.discrete_start,    m.discrete_kind,
        m.root_relation,      m.reinit_target,     m.terminate_message,
        m.threshold_relation, m.sample_discrete,   m.assert_message,
        m.assert_level,       m.assert_origin,     m.mode_discrete,
        m.mode_values,        m.dummy_of,          m.original_row};
    for (const void *p : pointers)
      EXPECT_EQ(p, nullptr);
    EXPECT_EQ(m.event_update, nullptr);
    EXPECT_EQ(m.time_events, nullptr);
    EXPECT_EQ(m.asserts, nullptr);
  });
}

TEST(Events, UpdateAtABounce) {
  // The ball just below the ground at t = 0.7 on a sample tick (the runtime
  // set the sample value to 1, its pre() is 0), count was 2.
  EventPoint bounce{0.7, -0.01, -3.0, {0, 0, 0, 0, 1, 2, 0},
                    {0, 0, 0, 0, 0, 2, 0}};
  // out = [7 discrete | reinit value | reinit fired | terminate fired].
  const std::vector<double> want = {1, 1, 1, 1, 1, 3, 0, 2.4, 1, 0};
  // The same with the when-condition already true before: no reinit; no
  // tick; before t0 = 0.5.
  EventPoint again{0.3, -0.01, -3.0, {1, 1, 0, 0, 1, 2, 0},
                   {1, 1, 0, 0, 1, 2, 0}};
  const std::vector<double> wantAgain = {1, 1, 0, 0, 1, 2, 0, 2.4, 0, 0};
  // Above hmax, at the threshold itself: `time >= t0` holds at t0 (its
  // right limit); the initial event's initial() copied through.
  EventPoint high{0.5, 12, 1, {0, 0, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 0, 0}};
  const std::vector<double> wantHigh = {0, 0, 1, 1, 0, 0, 1, -0.8, 0, 1};
  onEachBackend(samples::bouncingEvents(), [&](const ldae_model &m) {
    int rc = -1;
    auto got = call(m.event_update, want.size(), at(m, bounce), rc);
    EXPECT_EQ(rc, 0);
    for (size_t k = 0; k < want.size(); ++k)
      EXPECT_DOUBLE_EQ(got[k], want[k]) << "bounce out[" << k << "]";
    got = call(m.event_update, want.size(), at(m, again), rc);
    for (size_t k = 0; k < want.size(); ++k)
      EXPECT_DOUBLE_EQ(got[k], wantAgain[k]) << "again out[" << k << "]";
    got = call(m.event_update, want.size(), at(m, high), rc);
    for (size_t k = 0; k < want.size(); ++k)
      EXPECT_DOUBLE_EQ(got[k], wantHigh[k]) << "high out[" << k << "]";
    // The root of relation 0 is h itself.
    Point pt = at(m, bounce);
    double root = 0;
    EXPECT_EQ(m.roots(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(), &root), 0);
    EXPECT_EQ(root, -0.01);
  });
}

TEST(Events, TimeEventsReadTheParameters) {
  onEachBackend(samples::bouncingEvents(), [&](const ldae_model &m) {
    Point pt = at(m, {0, 1, 0, std::vector<double>(kDiscrete, 0),
                      std::vector<double>(kDiscrete, 0)});
    int rc = -1;
    // [threshold t0 | start ts, interval ti].
    EXPECT_EQ(call(m.time_events, 3, pt, rc),
              (std::vector<double>{0.5, 0.1, 0.2}));
    EXPECT_EQ(rc, 0);
    pt.p[2] = 0.75; // t0 given another value: read from p, not folded
    pt.p[4] = 0.25; // ti
    EXPECT_EQ(call(m.time_events, 3, pt, rc),
              (std::vector<double>{0.75, 0.1, 0.25}));
  });
}

TEST(Events, Asserts) {
  std::vector<double> zero(kDiscrete, 0);
  onEachBackend(samples::bouncingEvents(), [&](const ldae_model &m) {
    int rc = -1;
    EXPECT_EQ(call(m.asserts, 2, at(m, {0, 1, -3, zero, zero}), rc),
              (std::vector<double>{1, 1}));
    EXPECT_EQ(rc, 0);
    EXPECT_EQ(call(m.asserts, 2, at(m, {0, -0.002, -3, zero, zero}), rc),
              (std::vector<double>{0, 1}));
    EXPECT_EQ(call(m.asserts, 2, at(m, {0, 1, -150, zero, zero}), rc),
              (std::vector<double>{1, 0}));
  });
}

// Between events the residual reads the frozen value of `on` from p, never
// `time >= t0` itself: at t = 2 with on = 0 it still uses g/2.
TEST(Events, ResidualsReadFrozenDiscreteValues) {
  onEachBackend(samples::bouncingEvents(), [&](const ldae_model &m) {
    std::vector<double> d(kDiscrete, 0);
    d[Count] = 4;
    Point pt = at(m, {2.0, 1, -3, d, d});
    pt.yp = {-3, 0.5};
    double r[2], out[3];
    m.state_sets[0].residual(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(), r);
    EXPECT_DOUBLE_EQ(r[1], 0.5 + 9.81 / 2);
    ASSERT_EQ(m.outputs(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(), out), 0);
    EXPECT_EQ(out[0], 4); // count
    EXPECT_EQ(out[1], 0); // on
    pt.p[kParams + On] = 1;
    m.state_sets[0].residual(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(), r);
    EXPECT_DOUBLE_EQ(r[1], 0.5 + 9.81);
    // The pre() value does not enter the residual.
    pt.p[kParams + kDiscrete + On] = 0;
    double again[2];
    m.state_sets[0].residual(pt.t, pt.y.data(), pt.yp.data(), pt.p.data(),
                             again);
    EXPECT_EQ(again[1], r[1]);
  });
}

// A reinit value outside its domain: the event update returns 1 + its row
// in the output (after the 7 discrete values: row 7), in every backend.
TEST(Events, DomainErrorInTheUpdateNamesItsRow) {
  samples::SampleSystem s = samples::bouncingEvents();
  auto &c = s.sys.ctx;
  ir::ExprRef h = c->var(s.sys.unknowns[0].key);
  s.sys.events.reinits[0].value = c->call(ir::FuncKind::Sqrt, h);
  std::vector<double> zero(kDiscrete, 0);
  onEachBackend(std::move(s), [&](const ldae_model &m) {
    int rc = -1;
    call(m.event_update, 10, at(m, {0, -1, 0, zero, zero}), rc);
    EXPECT_EQ(rc, 1 + kDiscrete);
    call(m.event_update, 10, at(m, {0, 4, 0, zero, zero}), rc);
    EXPECT_EQ(rc, 0);
  });
}

TEST(Events, TablesThatDoNotFitAreRefused) {
  auto refused = [](auto edit) {
    samples::SampleSystem s = samples::bouncingEvents();
    edit(s.sys);
    auto plan = lowerToPlan(s.sys);
    return plan ? std::string("accepted") : plan.error();
  };
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.events.rootRelation = {9}; }),
            "events: root_relation 9 is out of range (7)");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.events.rootRelation.clear(); }),
            "events: root_relation has 0 entries for 1");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.events.update.pop_back(); }),
            "events: the update has 6 entries for 7");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.events.reinits[0].unknown = 2; }),
            "events: reinit target 2 is out of range (2)");
  EXPECT_EQ(
      refused([](ir::DaeSystem &s) { s.events.reinits[0].fired = nullptr; }),
      "events: a reinit has no expression");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.events.sampleDiscrete = {7}; }),
            "events: sample_discrete 7 is out of range (7)");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.events.modeValues.clear(); }),
            "events: mode_values has 0 entries for 1");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.dummyOf = {{-1, 5}}; }),
            "events: dummy_of 5 is out of range (2)");
  EXPECT_EQ(refused([](ir::DaeSystem &s) { s.originalRow = {{true}}; }),
            "events: original_row row has 1 entries for 2");
  // A discrete value read past the discrete state.
  EXPECT_EQ(refused([](ir::DaeSystem &s) {
              s.outputs[0].value = s.ctx->param(6 + 2 * 7);
            }),
            "in outputs: parameter index 20 is out of range");
}

// A run re-evaluates bindings over its parameters alone (ldae_model::bind):
// a start value that reads a discrete value reads its start there.
TEST(Events, BindingsReadDiscreteStarts) {
  samples::SampleSystem s = samples::bouncingEvents();
  s.sys.unknowns[0].startBinding =
      s.sys.ctx->add(samples::discreteValue(s.sys, Initial),
                     s.sys.ctx->param(5)); // initial() + hmax
  auto plan = lowerToPlan(s.sys);
  ASSERT_TRUE(bool(plan)) << plan.error();
  ASSERT_GE(plan->bind, 0);
  ASSERT_EQ(plan->boundStarts, std::vector<int>{0});
  std::vector<double> p = plan->paramValues; // n_params entries only
  p[5] = 20;
  double out = 0;
  EXPECT_EQ(interpret(plan->functions[plan->bind], 0, nullptr, nullptr,
                      p.data(), 0, &out, nullptr),
            0);
  EXPECT_EQ(out, 21);
}

} // namespace
