// Hand-built DaeSystems; see SampleSystems.h.
#include "SampleSystems.h"

#include <cmath>

namespace ldae::codegen::samples {

using ir::ExprRef;
using ir::FuncKind;
using ir::VarKey;

namespace {

/// Declares variables/parameters on a fresh Model and fills the system.
class Builder {
public:
  explicit Builder(const std::string &name) : s_{std::make_unique<ir::Model>(), {}} {
    s_.model->name = name;
    s_.sys.ctx = s_.model->sharedCtx();
    s_.sys.model = s_.model.get();
  }
  ir::ExprContext &c() { return s_.model->ctx(); }

  /// A model variable (not yet an unknown).
  ir::VarId variable(const std::string &name) {
    ir::Variable v;
    v.name = name;
    return s_.model->addVariable(v);
  }
  ExprRef param(const std::string &name, double value) {
    ir::Parameter p;
    p.name = name;
    p.value = value;
    ir::ParamId id = s_.model->addParameter(p);
    s_.sys.parameterNames.push_back(name);
    s_.sys.parameterValues.push_back(value);
    return c().param(id);
  }
  /// Appends an unknown slot holding Variable(key).
  void unknown(VarKey key, bool differential, double start,
               double startDerivative = 0) {
    ir::SystemUnknown u;
    u.key = key;
    u.name = s_.model->variableName(key);
    u.differential = differential;
    u.start = start;
    u.startDerivative = startDerivative;
    s_.sys.unknowns.push_back(u);
  }
  /// A variable that is also the next unknown slot; returns Variable(v).
  ExprRef state(const std::string &name, bool differential, double start,
                double startDerivative = 0) {
    ir::VarId v = variable(name);
    unknown({v, 0}, differential, start, startDerivative);
    return c().var(v);
  }
  ExprRef der(ExprRef v) { return c().var(v->var(), v->order() + 1); }
  void output(const std::string &name, ExprRef value) {
    s_.sys.outputs.push_back({name, value});
  }
  /// One state set with the unknowns' own differential flags.
  ir::StateSet &singleSet(std::vector<ExprRef> residuals) {
    ir::StateSet set;
    set.residuals = std::move(residuals);
    for (const ir::SystemUnknown &u : s_.sys.unknowns) {
      set.differential.push_back(u.differential);
      if (u.differential)
        set.states.push_back(u.name);
    }
    s_.sys.stateSets.push_back(std::move(set));
    return s_.sys.stateSets.back();
  }
  SampleSystem take() { return std::move(s_); }
  ir::Model &model() { return *s_.model; }
  ir::DaeSystem &sys() { return s_.sys; }

private:
  SampleSystem s_;
};

} // namespace

SampleSystem robertson() {
  Builder b("robertson");
  auto &c = b.c();
  ExprRef k1 = b.param("k1", 0.04), k2 = b.param("k2", 3e7),
          k3 = b.param("k3", 1e4);
  ExprRef y1 = b.state("y1", true, 1, -0.04), y2 = b.state("y2", true, 0, 0.04),
          y3 = b.state("y3", false, 0);
  ExprRef y2y3 = c.mul(k3, c.mul(y2, y3));
  ExprRef sum = c.sub(c.add(c.add(y1, y2), y3), c.one());
  b.singleSet({c.sub(b.der(y1), c.add(c.mul(c.neg(k1), y1), y2y3)),
               c.sub(b.der(y2), c.sub(c.sub(c.mul(k1, y1), y2y3),
                                      c.mul(k2, c.pow(y2, c.constant(2))))),
               sum});
  b.sys().initialResiduals = {c.sub(y1, c.one())};
  b.sys().roots = {c.sub(y1, c.constant(0.5))};
  b.sys().constraints = {sum};
  b.output("y1", y1);
  b.output("y2", y2);
  b.output("y3", y3);
  b.output("der(y1)", b.der(y1));
  b.model().experiment.stopTime = 0.4;
  b.model().experiment.interval = 0.04;
  return b.take();
}

SampleSystem pendulum() {
  Builder b("pendulum");
  auto &c = b.c();
  ExprRef g = b.param("g", 9.81), L = b.param("L", 1.0);
  ExprRef x = b.state("x", true, 0.6), y = b.state("y", false, -0.8),
          vx = b.state("vx", true, 0), vy = b.state("vy", false, 0),
          lam = b.state("lambda", false, 0.8 * 9.81);
  // Dummy derivatives of set A: der(y), der(vy).
  b.unknown({y->var(), 1}, false, 0);
  b.unknown({vy->var(), 1}, false, -9.81);
  ExprRef two = c.constant(2);
  std::vector<ExprRef> res = {
      c.sub(b.der(x), vx),
      c.sub(b.der(y), vy),
      c.add(b.der(vx), c.mul(lam, x)),
      c.add(c.add(b.der(vy), c.mul(lam, y)), g),
      c.sub(c.add(c.pow(x, two), c.pow(y, two)), c.pow(L, two)),
      c.add(c.mul(x, vx), c.mul(y, vy)),
      c.add(c.add(c.pow(vx, two), c.pow(vy, two)),
            c.add(c.mul(x, b.der(vx)), c.mul(y, b.der(vy))))};
  ir::StateSet &a = b.singleSet(res);
  a.pivotSize = 1;
  a.pivot = {c.mul(two, y)};
  ir::StateSet setB;
  setB.residuals = res;
  setB.differential = {false, true, false, true, false, false, false};
  setB.keys = {x->varKey(), y->varKey(), vx->varKey(), vy->varKey(),
               lam->varKey(), VarKey{x->var(), 1}, VarKey{vx->var(), 1}};
  setB.states = {"y", "vy"};
  setB.pivotSize = 1;
  setB.pivot = {c.mul(two, x)};
  b.sys().stateSets.push_back(setB);
  b.sys().constraints = {res[4], res[5]};
  b.output("x", x);
  b.output("y", y);
  b.output("energy",
           c.add(c.mul(c.constant(0.5), c.add(c.pow(vx, two), c.pow(vy, two))),
                 c.mul(g, y)));
  b.output("lambda", lam);
  return b.take();
}

namespace {

/// chain(n); `shuffle` declares the unknowns in a scrambled order;
/// `initial` adds initial equations.
SampleSystem makeChain(unsigned n, bool shuffle, bool initial = false) {
  Builder b((initial  ? "init_chain"
             : shuffle ? "shuffled_chain"
                       : "chain") +
            std::to_string(n));
  auto &c = b.c();
  ExprRef k = b.param("k", 1.5), a = b.param("a", 0.1);
  std::vector<ExprRef> x(n);
  for (unsigned j = 0; j < n; ++j) {
    // i -> 7i + 3 mod n is a permutation when gcd(7, n) = 1.
    unsigned i = shuffle && n % 7 ? (7 * j + 3) % n : j;
    x[i] = b.state("x[" + std::to_string(i + 1) + "]", true,
                   std::sin(double(i)));
  }
  std::vector<ExprRef> res;
  for (unsigned i = 0; i < n; ++i) {
    ExprRef lap = c.mul(c.constant(-2), x[i]);
    if (i > 0)
      lap = c.add(lap, x[i - 1]);
    if (i + 1 < n)
      lap = c.add(lap, x[i + 1]);
    ExprRef rhs = c.sub(c.mul(k, lap), c.mul(a, c.pow(x[i], c.constant(3))));
    if (i == 0)
      rhs = c.add(rhs, c.call(FuncKind::Sin, c.time()));
    res.push_back(c.sub(b.der(x[i]), rhs));
  }
  b.singleSet(res);
  if (initial)
    for (unsigned i = 1; i < n; i += 2)
      b.sys().initialResiduals.push_back(
          c.sub(c.mul(b.der(x[i]), x[i - 1]),
                c.mul(c.constant(0.1), c.pow(x[i], c.constant(2)))));
  b.output("x[1]", x.front());
  b.output("x[" + std::to_string(n) + "]", x.back());
  return b.take();
}

} // namespace

SampleSystem robertsonSga(bool project) {
  Builder b("robertson_sga");
  auto &c = b.c();
  ExprRef k1 = b.param("k1", 0.04), k2 = b.param("k2", 3e7),
          k3 = b.param("k3", 1e4);
  ExprRef y1 = b.state("y1", true, 1), y2 = b.state("y2", true, 0),
          y3 = b.state("y3", true, 0);
  ExprRef y2y3 = c.mul(k3, c.mul(y2, y3));
  std::vector<ExprRef> rates = {b.der(y1), b.der(y2), b.der(y3)};
  b.singleSet({c.sub(b.der(y1), c.add(c.mul(c.neg(k1), y1), y2y3)),
               c.sub(b.der(y2), c.sub(c.sub(c.mul(k1, y1), y2y3),
                                      c.mul(k2, c.pow(y2, c.constant(2))))),
               c.add(rates)});
  b.sys().constraints = {c.sub(c.add(c.add(y1, y2), y3), c.one())};
  b.sys().form = ir::SystemForm::LinearlyImplicit;
  b.sys().projectOntoConstraints = project;
  b.output("y1", y1);
  b.output("y2", y2);
  b.output("y3", y3);
  return b.take();
}

SampleSystem cartesianPendulumSga(double theta0, bool project) {
  Builder b("pendulum_sga");
  auto &c = b.c();
  const double gv = 9.81, Lv = 1.0;
  ExprRef g = b.param("g", gv), L = b.param("L", Lv);
  ExprRef x = b.state("x", true, Lv * std::sin(theta0)),
          y = b.state("y", true, -Lv * std::cos(theta0)),
          u = b.state("u", true, 0), v = b.state("v", true, 0),
          lam = b.state("lambda", true, gv * std::cos(theta0) / Lv);
  ExprRef two = c.constant(2);
  ExprRef r2 = c.add(c.pow(x, two), c.pow(y, two));
  ExprRef c1 = c.sub(r2, c.pow(L, two));
  ExprRef c2 = c.add(c.mul(x, u), c.mul(y, v));
  ExprRef c3 = c.sub(c.sub(c.add(c.pow(u, two), c.pow(v, two)), c.mul(lam, r2)),
                     c.mul(g, y));
  // d/dt c3 = 2 u u' + 2 v v' - lambda' r2 - 2 lambda (x x' + y y') - g y'.
  std::vector<ExprRef> terms = {
      c.mul(two, c.mul(u, b.der(u))), c.mul(two, c.mul(v, b.der(v))),
      c.neg(c.mul(b.der(lam), r2)),
      c.neg(c.mul(two, c.mul(lam, c.add(c.mul(x, b.der(x)),
                                        c.mul(y, b.der(y)))))),
      c.neg(c.mul(g, b.der(y)))};
  ExprRef dc3 = c.add(terms);
  b.singleSet({c.sub(b.der(x), u), c.sub(b.der(y), v),
               c.add(b.der(u), c.mul(lam, x)),
               c.add(c.add(b.der(v), c.mul(lam, y)), g), dc3});
  b.sys().constraints = {c1, c2, c3};
  b.sys().form = ir::SystemForm::LinearlyImplicit;
  b.sys().projectOntoConstraints = project;
  for (ExprRef e : {x, y, u, v, lam})
    b.output(b.model().variableName(e->varKey()), e);
  return b.take();
}

SampleSystem chain(unsigned n) { return makeChain(n, false); }

SampleSystem shuffledChain(unsigned n) { return makeChain(n, true); }

SampleSystem initChain(unsigned n) { return makeChain(n, false, true); }

SampleSystem logSum(unsigned n) {
  Builder b("log_sum" + std::to_string(n));
  auto &c = b.c();
  std::vector<ExprRef> res, logs;
  for (unsigned i = 0; i < n; ++i) {
    ExprRef x = b.state("x[" + std::to_string(i + 1) + "]", false, std::sqrt(2));
    res.push_back(c.sub(c.pow(x, c.constant(2)), c.constant(2)));
    logs.push_back(c.call(FuncKind::Log, x));
  }
  ExprRef s = b.state("s", false, 0);
  res.push_back(c.sub(s, c.add(logs)));
  b.output("s", s);
  b.singleSet(res);
  return b.take();
}

SampleSystem logChain(unsigned n) {
  Builder b("log_chain" + std::to_string(n));
  auto &c = b.c();
  std::vector<ExprRef> res;
  for (unsigned i = 0; i < n; ++i) {
    ExprRef x = b.state("x[" + std::to_string(i + 1) + "]", false, std::exp(1));
    res.push_back(c.sub(c.call(FuncKind::Log, x), c.constant(1)));
  }
  b.singleSet(res);
  return b.take();
}

SampleSystem builtins() {
  Builder b("builtins");
  auto &c = b.c();
  ExprRef u = b.state("u", true, 0.3), v = b.state("v", true, 0.6);
  ExprRef p = b.param("p", 1.25);
  using ir::CompareKind;
  auto k = [&](double x) { return c.constant(x); };
  auto call = [&](FuncKind f, ExprRef a) { return c.call(f, a); };
  std::vector<std::pair<std::string, ExprRef>> fs = {
      {"sin", call(FuncKind::Sin, u)},
      {"cos", call(FuncKind::Cos, u)},
      {"tan", call(FuncKind::Tan, u)},
      {"asin", call(FuncKind::Asin, u)},
      {"acos", call(FuncKind::Acos, u)},
      {"atan", call(FuncKind::Atan, u)},
      {"atan2", c.call(FuncKind::Atan2, u, v)},
      {"sinh", call(FuncKind::Sinh, u)},
      {"cosh", call(FuncKind::Cosh, u)},
      {"tanh", call(FuncKind::Tanh, u)},
      {"exp", call(FuncKind::Exp, u)},
      {"log", call(FuncKind::Log, u)},
      {"log10", call(FuncKind::Log10, v)},
      {"sqrt", call(FuncKind::Sqrt, u)},
      {"abs", call(FuncKind::Abs, c.sub(u, v))},
      {"sign", c.mul(call(FuncKind::Sign, c.sub(u, v)), v)},
      {"min", c.call(FuncKind::Min, u, v)},
      {"max", c.call(FuncKind::Max, u, v)},
      {"floor", c.mul(call(FuncKind::Floor, c.mul(k(4), u)), v)},
      {"ceil", c.mul(call(FuncKind::Ceil, c.mul(k(4), u)), v)},
      {"mod", c.call(FuncKind::Mod, c.mul(k(5), u), v)},
      {"pow", c.pow(u, v)},
      {"cube", c.pow(u, k(3))},
      {"pow7", c.pow(c.add(u, v), k(7))},
      {"inverse_square", c.pow(v, k(-2))},
      {"pow_half", c.pow(c.add(u, v), k(0.5))},
      {"pow_param", c.pow(v, p)},
      {"quotient", c.div(c.sub(u, k(1)), c.add(v, u))},
      {"if", c.ifThenElse(c.compare(CompareKind::Gt, u, v), c.mul(u, v),
                          c.sub(u, v))},
      {"and", c.ifThenElse(c.logicalAnd(c.compare(CompareKind::Le, u, v),
                                        c.compare(CompareKind::Ge, v, k(0.1))),
                           c.mul(u, u), v)},
      {"or", c.ifThenElse(c.logicalOr(c.compare(CompareKind::Lt, u, k(0)),
                                      c.compare(CompareKind::Eq, u, v)),
                          u, c.mul(k(2), v))},
      {"not", c.ifThenElse(c.logicalNot(c.compare(CompareKind::Ne, u, v)),
                           k(3), c.mul(u, k(4)))},
      {"time", c.mul(call(FuncKind::Sin, c.time()), u)},
  };
  std::vector<ExprRef> zs;
  for (auto &[name, f] : fs)
    zs.push_back(b.state("z_" + name, false, 0));
  std::vector<ExprRef> res = {c.sub(b.der(u), v), c.add(b.der(v), u)};
  for (size_t i = 0; i < fs.size(); ++i) {
    res.push_back(c.sub(zs[i], fs[i].second));
    b.output(fs[i].first, fs[i].second);
  }
  b.singleSet(res);
  return b.take();
}

SampleSystem domainErrors() {
  Builder b("domain");
  auto &c = b.c();
  using ir::CompareKind;
  auto k = [&](double x) { return c.constant(x); };
  ExprRef x = b.state("x", false, 2);
  std::vector<ExprRef> rhs = {
      c.ifThenElse(c.compare(CompareKind::Gt, x, k(100)),
                   c.call(FuncKind::Log, c.sub(x, k(200))), k(0)),
      c.call(FuncKind::Log, x),
      c.call(FuncKind::Sqrt, c.sub(x, k(1))),
      c.div(k(1), c.sub(x, k(3))),
      c.ifThenElse(c.compare(CompareKind::Gt, x, k(0)),
                   c.call(FuncKind::Log, x), k(0)),
      c.call(FuncKind::Asin, c.div(c.sub(x, k(4)), k(4))),
      c.call(FuncKind::Mod, x, c.sub(x, k(5))),
      c.ifThenElse(c.compare(CompareKind::Lt, x, k(5.8)), k(1),
                   c.pow(c.sub(x, k(6.2)), k(1.5))),
  };
  const char *names[] = {"h", "a", "b", "c", "d", "e", "f", "g"};
  std::vector<ExprRef> res = {c.sub(x, k(2))};
  for (size_t i = 0; i < rhs.size(); ++i)
    res.push_back(c.sub(b.state(names[i], false, 0), rhs[i]));
  b.singleSet(res);
  return b.take();
}

SampleSystem pendulumPencil() {
  SampleSystem s = pendulum();
  s.model->name = "pendulum_pencil";
  s.sys.dummyOf = {{-1, -1, -1, -1, -1, 1, 3}, {-1, -1, -1, -1, -1, 0, 2}};
  const std::vector<bool> written = {true, true, true, true, true, false,
                                     false};
  s.sys.originalRow = {written, written};
  return s;
}

ExprRef discreteValue(const ir::DaeSystem &sys, unsigned k) {
  return sys.ctx->param(sys.parameterValues.size() + k);
}

ExprRef discretePre(const ir::DaeSystem &sys, unsigned k) {
  return sys.ctx->param(sys.parameterValues.size() +
                        sys.events.discrete.size() + k);
}

SampleSystem bouncingEvents() {
  Builder b("bouncing_events");
  auto &c = b.c();
  using ir::CompareKind;
  using ir::DiscreteKind;
  ExprRef g = b.param("g", 9.81), e = b.param("e", 0.8),
          t0 = b.param("t0", 0.5), ts = b.param("ts", 0.1),
          ti = b.param("ti", 0.2), hmax = b.param("hmax", 10);
  ExprRef h = b.state("h", true, 1), v = b.state("v", true, 0);
  ir::EventSystem &ev = b.sys().events;
  ev.discrete = {{"h <= 0", DiscreteKind::Relation, 0},
                 {"when h <= 0", DiscreteKind::When, 0},
                 {"time >= t0", DiscreteKind::Relation, 0},
                 {"on", DiscreteKind::Variable, 0},
                 {"sample(ts, ti)", DiscreteKind::Sample, 0},
                 {"count", DiscreteKind::Variable, 0},
                 {"initial()", DiscreteKind::Initial, 1}};
  auto d = [&](unsigned k) { return discreteValue(b.sys(), k); };
  auto pre = [&](unsigned k) { return discretePre(b.sys(), k); };
  ExprRef ground = c.compare(CompareKind::Le, h, c.zero());
  ExprRef late = c.compare(CompareKind::Ge, c.time(), t0);
  ExprRef tick = c.logicalAnd(d(4), c.logicalNot(pre(4)));
  ev.update = {ground, ground, late, late, d(4),
               c.ifThenElse(tick, c.add(pre(5), c.one()), pre(5)), d(6)};
  b.sys().roots = {h};
  ev.rootRelation = {0};
  ev.reinits = {{1, c.mul(c.neg(e), c.pre(v->var())),
                 c.logicalAnd(ground, c.logicalNot(pre(1)))}};
  ev.terminates = {{c.compare(CompareKind::Gt, h, hmax), "too high"}};
  ev.timeThresholds = {t0};
  ev.thresholdRelation = {2};
  ev.samples = {{ts, ti}};
  ev.sampleDiscrete = {4};
  ev.asserts = {
      {c.compare(CompareKind::Ge, h, c.constant(-0.001)), "below ground", 0,
       {}, {}},
      {c.compare(CompareKind::Lt, c.call(FuncKind::Abs, v), c.constant(100)),
       "too fast", 1, {}, {}}};
  ev.modeDiscrete = {3};
  ev.modeValues = {0};
  b.singleSet({c.sub(b.der(h), v),
               c.add(b.der(v), c.ifThenElse(d(3), g, c.div(g, c.constant(2))))});
  b.sys().dummyOf = {{-1, -1}};
  b.sys().originalRow = {{true, true}};
  b.output("count", d(5));
  b.output("on", d(3));
  b.output("energy", c.add(c.mul(g, h), c.div(c.pow(v, c.constant(2)),
                                              c.constant(2))));
  return b.take();
}

} // namespace ldae::codegen::samples
