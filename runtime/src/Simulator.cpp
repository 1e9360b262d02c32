// The simulation driver (see ldae/Simulation.h): resolve options, find a
// consistent initial point, step the integrator (IDA or CVODE, behind
// Integrator.h) one internal step at a time, interpolate onto the output
// grid, switch state sets when the current one's pivot degrades, and keep
// the results of a failed run.
#include "ldae/Simulation.h"
#include "ConsistentInit.h"
#include "SparseInit.h"
#include "FailureReport.h"
#include "Integrator.h"
#include "Progress.h"
#include "ResultWriter.h"
#include "StateSelection.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <ostream>

namespace ldae::runtime {

namespace {

double pick(const std::optional<double> &opt, double fromModel, double dflt) {
  if (opt)
    return *opt;
  return std::isnan(fromModel) ? dflt : fromModel;
}

/// Resolved settings of one run.
struct RunSettings {
  double start, stop, rtol, atol, interval;
};

Expected<RunSettings> resolve(const ldae_model &m, const SimOptions &o) {
  RunSettings s;
  s.start = pick(o.start, m.start_time, 0.0);
  s.stop = pick(o.stop, m.stop_time, 1.0);
  s.rtol = pick(o.rtol, m.tolerance, 1e-6);
  s.atol = o.atol ? *o.atol : s.rtol;
  s.interval = pick(o.interval, m.interval, (s.stop - s.start) / 500);
  // Non-finite times or tolerances make every later computation NaN (or
  // an endless run); the driver rejects them on its command line already,
  // this catches the experiment annotation and other callers.
  for (auto [what, v] : {std::pair{"start time", s.start}, {"stop time", s.stop},
                         {"rtol", s.rtol}, {"atol", s.atol}})
    if (!std::isfinite(v))
      return Error{fmt::format("the {} {} is not finite", what, v)};
  if (o.interval && !std::isfinite(*o.interval))
    return Error{fmt::format("the output interval {} is not finite",
                             *o.interval)};
  if (!(s.stop >= s.start))
    return Error{fmt::format("the stop time {} is before the start time {}",
                             s.stop, s.start)};
  if (!(s.rtol > 0) || !(s.atol > 0))
    return Error{"tolerances must be positive"};
  if (!(s.interval > 0) && s.stop > s.start)
    return Error{"the output interval must be positive"};
  if (s.stop > s.start && o.times.empty() && !o.everyStep &&
      outputRows(s.start, s.stop, s.interval) > kMaxOutputRows)
    return Error{tooManyRowsMessage(s.start, s.stop, s.interval)};
  for (size_t i = 0; i < o.times.size(); ++i)
    if (!(o.times[i] > s.start && o.times[i] <= s.stop) ||
        (i > 0 && !(o.times[i] > o.times[i - 1])))
      return Error{"output times must increase within (start, stop]"};
  return s;
}

Expected<std::vector<double>> resolveParams(const ldae_model &m,
                                            const SimOptions &o) {
  std::vector<double> p(m.param_values, m.param_values + m.n_params);
  std::vector<std::string> names;
  for (int i = 0; i < m.n_params; ++i)
    names.push_back(m.param_names && m.param_names[i] ? m.param_names[i] : "");
  for (const auto &[name, value] : o.params) {
    auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      return unknownNameError("parameter", name, names);
    p[it - names.begin()] = value;
  }
  return p;
}

/// Collects rows and the drift maximum.
class Recorder {
public:
  Recorder(const ModelEval &ev, std::vector<int> cols, SimResult &res)
      : ev_(ev), m_(ev.model()), cols_(std::move(cols)), res_(res),
        out_(std::max(m_.n_outputs, 0)), drift_(std::max(m_.n_drift, 0)) {}

  /// Appends the row at `t`; false (and the failure) when an output left
  /// its domain there: the rows so far are kept, the run stops.
  bool record(double t, const double *y, const double *yp) {
    std::vector<double> row{t};
    const double *src = y;
    if (m_.n_outputs > 0) {
      int rc = m_.outputs(t, y, yp, ev_.params(), out_.data());
      if (rc != 0) {
        double lastGood = res_.rows.empty() ? t : res_.rows.back()[0];
        res_.failure =
            rc > 0 ? describeOutputDomainError(ev_, rc - 1, t, lastGood, y)
                   : fmt::format("simulation failed at t = {:.10g}: the "
                                 "outputs could not be computed",
                                 t);
        return false;
      }
      src = out_.data();
    }
    for (int c : cols_)
      row.push_back(src[c]);
    res_.rows.push_back(std::move(row));
    if (m_.n_drift > 0 && m_.drift &&
        m_.drift(t, y, yp, ev_.params(), drift_.data()) == 0)
      for (double d : drift_)
        res_.stats.maxDrift = std::max(res_.stats.maxDrift, std::fabs(d));
    return true;
  }

private:
  const ModelEval &ev_;
  const ldae_model &m_;
  std::vector<int> cols_;
  SimResult &res_;
  std::vector<double> out_, drift_;
};

/// The most steps between two output times (of the interval grid, also
/// with --every-step or explicit times): a solution that blows up or
/// oscillates ever faster would otherwise step for ever (the solvers'
/// own limit, mxstep, counts steps per solver call, and each of our calls
/// is one step). SUNDIALS' own default is 500 per output.
constexpr long kMaxStepsPerOutput = 100000;

/// Above this many unknowns the general initialization (dense Wong
/// sequences and least squares on n x 2n matrices, O(n^3)) would need hours
/// and gigabytes; it fails with a message instead.
constexpr int kMaxDenseInitUnknowns = 10000;

/// Hands a consistent point found by our own Newton iteration to IDA.
bool adoptInitialPoint(const ModelEval &ev, Integrator &ida, int set,
                       double t0, const std::vector<double> &y0,
                       const InitOutcome &init, SimResult &res,
                       std::ostream *log) {
  reportMoves(ev, y0, init.y.data(), log);
  auto re = ida.reinit(set, t0, init.y.data(), init.yp.data());
  if (!re) {
    res.failure = describeSolverError(t0, re.error());
    return false;
  }
  return true;
}

/// The message of a failed initialization: a domain error in the same form
/// as one during the run (FailureReport), else the outcome's own text.
std::string initFailure(const ModelEval &ev, int set, double t0,
                        const InitOutcome &init) {
  if (init.domainRow >= 0)
    return describeInitDomainError(ev, set, init.domainRow,
                                   init.domainY.data(), t0);
  return fmt::format("initialization failed at t = {}: {}", t0, init.failure);
}

/// Finds the initial point from the start vector (y, yp) (IDA holds it);
/// returns false (with the failure filled in) when there is none.
bool initializeFrom(const ModelEval &ev, Integrator &ida, int set,
                    double t0, double tNext, std::vector<double> y,
                    std::vector<double> yp, SimResult &res,
                    std::ostream *log) {
  int n = ev.n();
  if (isPlainIndexOne(ev, set, t0, y.data(), yp.data())) {
    if (ida.completeStart(tNext).ok()) {
      if (log)
        *log << "initialization: index-1 structure; algebraic values and "
                "derivatives solved from the differential start values\n";
      reportMoves(ev, y, ida.y(), log);
      return true;
    }
    if (usesSparseInit(ev)) {
      // The same rule by our own Newton iteration (tighter tolerance, no
      // dependence on the first output time), still sparse.
      InitOutcome init = initializeIndexOne(ev, set, t0, y, yp);
      if (!init.ok && init.domainRow >= 0) {
        res.failure = initFailure(ev, set, t0, init);
        return false;
      }
      if (init.ok) {
        if (log)
          *log << "initialization: IDACalcIC failed; index-1 Newton "
                  "iteration (sparse) solved the algebraic values and "
                  "derivatives\n";
        return adoptInitialPoint(ev, ida, set, t0, y, init, res, log);
      }
    }
    if (log)
      *log << "initialization: IDACalcIC failed; trying Newton steps along "
              "the jump space\n";
    auto re = ida.reinit(set, t0, y.data(), yp.data());
    if (!re) {
      res.failure = describeSolverError(t0, re.error());
      return false;
    }
  }
  if (usesSparseInit(ev)) {
    InitOutcome init = initializeSparse(ev, set, t0, y, yp);
    if (init.ok) {
      if (log)
        *log << fmt::format(
            "initialization: sparse Newton iteration (KLU) on the residuals, "
            "fixed values and initial equations; {} differential values "
            "kept, {} moved by the conditions{}\n",
            init.kept, init.moved,
            init.projected ? fmt::format(" ({} in minimum-norm blocks)",
                                         init.projected)
                           : std::string());
      return adoptInitialPoint(ev, ida, set, t0, y, init, res, log);
    }
    if (init.applicable) {
      res.failure = initFailure(ev, set, t0, init);
      return false;
    }
    if (log)
      *log << "initialization: the sparse path does not apply (" +
                  init.failure + "); using the dense one\n";
    if (n > kMaxDenseInitUnknowns) {
      res.failure = fmt::format(
          "initialization failed at t = {}: {}; and the general "
          "initialization along the jump space is dense: {} unknowns are "
          "more than it handles ({})",
          t0, init.failure, n, kMaxDenseInitUnknowns);
      return false;
    }
  }
  if (n > kMaxDenseInitUnknowns) {
    res.failure = fmt::format(
        "initialization failed at t = {}: the model is not plain index-1 at "
        "the start values (or has initial equations or fixed algebraic "
        "values), and the general initialization along the jump space is "
        "dense: {} unknowns are more than it handles ({})",
        t0, n, kMaxDenseInitUnknowns);
    return false;
  }
  InitOutcome init = initializeAlongJumps(ev, set, t0, y, yp, log);
  if (!init.ok) {
    res.failure = initFailure(ev, set, t0, init);
    return false;
  }
  if (log)
    *log << fmt::format("initialization: start values moved along the jump "
                        "space T (dimension {}, index {}){}\n",
                        init.jumpDim, init.index,
                        init.nearestPoint ? "; nearest point used" : "");
  return adoptInitialPoint(ev, ida, set, t0, y, init, res, log);
}

/// The continuation of homotopy(): from the simplified model (lambda = 0),
/// solved from the start values, to the actual one (lambda = 1), each
/// initialization starting from the last; the step in lambda grows after a
/// success and halves after a failure.
bool homotopyContinuation(ModelEval &ev, Integrator &ida, int set,
                          double t0, double tNext, int lambda, SimResult &res,
                          std::ostream *log) {
  const ldae_model &m = ev.model();
  int n = ev.n();
  std::vector<double> y(m.start_y, m.start_y + n),
      yp(m.start_yp, m.start_yp + n);
  auto from = [&](double l) {
    ev.setParam(lambda, l);
    res.failure.clear();
    auto re = ida.reinit(set, t0, y.data(), yp.data());
    return re && initializeFrom(ev, ida, set, t0, tNext, y, yp, res, nullptr);
  };
  if (!from(0.0)) {
    ev.setParam(lambda, 1.0);
    res.failure = "the simplified model of homotopy() (lambda = 0) does not "
                  "initialize either: " + res.failure;
    return false;
  }
  double l = 0, step = 0.1;
  int steps = 0;
  while (l < 1) {
    y.assign(ida.y(), ida.y() + n);
    yp.assign(ida.yp(), ida.yp() + n);
    double next = std::min(1.0, l + step);
    if (from(next)) {
      l = next;
      ++steps;
      step *= 1.5;
      continue;
    }
    step /= 2;
    if (step < 1e-6) {
      ev.setParam(lambda, 1.0);
      res.failure = fmt::format("the homotopy continuation stalled at lambda "
                                "= {:.6g}: ",
                                l) +
                    res.failure;
      return false;
    }
    // Back to the last point reached.
    ev.setParam(lambda, l);
  }
  if (log)
    *log << fmt::format("initialization: homotopy continuation from the "
                        "simplified model to the actual one in {} steps\n",
                        steps);
  return true;
}

/// Finds the initial point from the start values; where that fails and the
/// model has homotopy(), continues from its simplified model. Returns false
/// (with the failure filled in) when there is none.
bool initialize(ModelEval &ev, Integrator &ida, int set, double t0,
                double tNext, SimResult &res, std::ostream *log) {
  const ldae_model &m = ev.model();
  int n = ev.n();
  std::vector<double> y(m.start_y, m.start_y + n),
      yp(m.start_yp, m.start_yp + n);
  if (initializeFrom(ev, ida, set, t0, tNext, y, yp, res, log))
    return true;
  int lambda = ev.paramIndex("homotopy.lambda");
  if (lambda < 0 || ev.params()[lambda] != 1.0)
    return false;
  std::string direct = res.failure;
  if (log)
    *log << "initialization: failed from the start values; trying the "
            "homotopy continuation\n";
  if (homotopyContinuation(ev, ida, set, t0, tNext, lambda, res, log))
    return true;
  res.failure = direct + "\n  homotopy continuation: " + res.failure;
  return false;
}

/// Restarts IDA at the current point with state set `to`.
bool switchStates(const ModelEval &ev, Integrator &ida, int to, double t,
                  double tNext, const std::vector<double> &cond, SimResult &res,
                  std::ostream *log) {
  int from = ida.set();
  int n = ev.n();
  std::vector<double> y(ida.y(), ida.y() + n), yp(ida.yp(), ida.yp() + n);
  auto re = ida.reinit(to, t, y.data(), yp.data());
  if (!re) {
    res.failure = describeSolverError(t, re.error());
    return false;
  }
  StepStatus started = ida.completeStart(tNext);
  if (!started.ok()) {
    res.failure = describeInitFailure(ev, ida, started, t) +
                  " (after switching state sets)";
    return false;
  }
  ++res.stats.stateSwitches;
  if (log) {
    auto desc = [&](int k) {
      const char *d = ev.set(k).description;
      return d ? std::string(d) : fmt::format("set {}", k);
    };
    *log << fmt::format("t = {:.10g}: state selection switched from '{}' to "
                        "'{}' (pivot condition {:.3g} -> {:.3g})\n",
                        t, desc(from), desc(to), cond[from], cond[to]);
  }
  return true;
}

} // namespace

double outputRows(double start, double stop, double interval) {
  // In double: a tiny interval overflows a long.
  return 1 + std::max(1.0, std::ceil((stop - start) / interval - 1e-9));
}

std::string tooManyRowsMessage(double start, double stop, double interval) {
  return fmt::format("the output interval {} from {} to {} gives {:.3g} rows, "
                     "more than the limit of {:.0e}; use a larger --interval",
                     interval, start, stop, outputRows(start, stop, interval),
                     kMaxOutputRows);
}

Expected<SimResult> simulate(const ldae_model &m, const SimOptions &o) {
  auto wall0 = std::chrono::steady_clock::now();
  if (m.abi_version != LDAE_ABI_VERSION)
    return Error{fmt::format("model ABI version {} does not match the "
                             "runtime's {}",
                             m.abi_version, LDAE_ABI_VERSION)};
  if (m.n_state_sets < 1 || !m.state_sets)
    return Error{"the model has no state set"};
  auto settings = resolve(m, o);
  if (!settings)
    return Error{settings.error()};
  auto params = resolveParams(m, o);
  if (!params)
    return Error{params.error()};
  const RunSettings &s = *settings;

  std::vector<std::string> available;
  for (int i = 0; i < (m.n_outputs > 0 ? m.n_outputs : m.n); ++i) {
    const char *name = m.n_outputs > 0
                           ? m.output_names[i]
                           : (m.var_names ? m.var_names[i] : nullptr);
    available.push_back(name ? name : fmt::format("y[{}]", i));
  }
  std::vector<int> cols;
  if (o.outputs.empty()) {
    for (size_t i = 0; i < available.size(); ++i)
      cols.push_back(int(i));
  } else {
    auto sel = selectColumns(available, o.outputs);
    if (!sel)
      return Error{sel.error()};
    cols = *sel;
  }

  SimResult res;
  res.columns.push_back("time");
  for (int c : cols)
    res.columns.push_back(available[c]);
  ModelEval ev(m, *params);
  Recorder rec(ev, cols, res);
  res.stats.n = m.n;
  auto finish = [&](Integrator *ida) -> Expected<SimResult> {
    if (ida) {
      ida->addCounters(res.stats);
      res.stats.sparse = ida->sparse();
      res.stats.integrator = ida->name();
    }
    res.stats.wallTime =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0)
            .count();
    if (!res.failure.empty())
      res.status = 3;
    return res;
  };

  double span = s.stop - s.start;
  // Output grid start + k * interval, the last point exactly stop.
  long nOut = !o.times.empty() ? long(o.times.size())
               : span > 0 ? outputRows(s.start, s.stop, s.interval) - 1
                          : 0;
  auto gridTime = [&](long k) {
    if (!o.times.empty())
      return o.times[k - 1];
    return k >= nOut ? s.stop : s.start + double(k) * s.interval;
  };

  if (m.n == 0) {
    // Nothing left to integrate (alias elimination and constant folding
    // solved everything): every output is a closed-form function of time.
    // SUNDIALS cannot take an empty system (N_VMin of a length-0 vector
    // reads element 0), so evaluate the outputs at the output times.
    // Without solver steps, --every-step reports the same grid.
    const double none = 0; // y and y' of length 0, never read
    if (rec.record(s.start, &none, &none))
      for (long k = 1; span > 0 && k <= nOut; ++k)
        if (!rec.record(gridTime(k), &none, &none))
          break;
    return finish(nullptr);
  }

  // Start with the best-conditioned state set at the start values.
  int set = 0;
  std::vector<double> cond =
      pivotConditions(ev, s.start, m.start_y, m.start_yp);
  set = chooseStateSet(cond, 0);

  ErrorWeights weights(ev, s.rtol, s.atol);
  const bool errorTestAlgebraic =
      o.algebraicErrorTest.value_or(m.algebraic_error_test != 0);
  double tNext = s.start + (span > 0 ? std::min(s.interval, span) : 1e-6);
  auto made = makeIntegrator(ev, o.integrator);
  if (!made)
    return Error{made.error()};
  Integrator &ida = **made;
  // IDA and CVODE need stop > start; a zero-length run still initializes.
  // The variables computed outside the integrator are error-tested with
  // the algebraic unknowns (docs/runtime.md, "The error test").
  if (errorTestAlgebraic && weights.propagates())
    ida.weighErrors(&weights);
  auto ok = ida.init(set, s.start, m.start_y, m.start_yp, s.rtol,
                     weights.atol(), span > 0 ? s.stop : s.start + 1e-6,
                     errorTestAlgebraic);
  if (!ok) {
    // The options were fine; a SUNDIALS call failing from here on is a
    // numerical failure of this run (status 3), never a command-line error.
    res.failure = describeSolverError(s.start, ok.error());
    return finish(&ida);
  }
  auto init0 = std::chrono::steady_clock::now();
  bool initialized = initialize(ev, ida, set, s.start, tNext, res, o.log);
  res.stats.initTime =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - init0)
          .count();
  if (!initialized)
    return finish(&ida);
  if (!rec.record(s.start, ida.y(), ida.yp()) || span <= 0)
    return finish(&ida);

  // The integrator steps freely up to the stop time; output times it steps
  // over are interpolated from the last step's polynomial (computed
  // variables are evaluated there by the outputs function). A stop time
  // per output would cost steps and Jacobian refreshes (docs/runtime.md).
  long k = 1; // next output time (of the grid, also with --every-step)
  Progress progress(o.progress, s.start, s.stop);
  double t = s.start;
  int tinySteps = 0; // consecutive steps at round-off level
  long stepsSinceOutput = 0;
  std::vector<double> yAt(m.n), ypAt(m.n);
  if (auto target = ida.setStopTime(s.stop); !target) {
    res.failure = describeSolverError(s.start, target.error());
    return finish(&ida);
  }
  while (true) {
    StepStatus st = ida.step(t);
    if (st.ok() && ida.lastStep() <= 1e4 * 2.2e-16 * std::fabs(t))
      ++tinySteps;
    else
      tinySteps = 0;
    if (tinySteps > 20)
      st = StepStatus::failed(FailureKind::StepCollapsed, "step size collapse");
    if (st.ok() && ++stepsSinceOutput > kMaxStepsPerOutput)
      st = StepStatus::failed(
          FailureKind::TooMuchWork,
          fmt::format("more than {} steps between output times",
                      kMaxStepsPerOutput));
    if (!st.ok()) {
      res.failure = describeFailure(ev, ida, st, ida.currentTime());
      break;
    }
    bool recorded = !o.everyStep || rec.record(t, ida.y(), ida.yp());
    for (; recorded && k <= nOut && gridTime(k) <= t; ++k) {
      stepsSinceOutput = 0;
      double tk = gridTime(k);
      if (o.everyStep)
        continue;
      if (tk == t) {
        recorded = rec.record(t, ida.y(), ida.yp());
        continue;
      }
      auto at = ida.interpolate(tk, yAt.data(), ypAt.data());
      if (!at) {
        res.failure = describeSolverError(tk, at.error());
        recorded = false;
        break;
      }
      recorded = rec.record(tk, yAt.data(), ypAt.data());
    }
    if (!recorded)
      break;
    if (st.kind == StepStatus::Root && o.log) {
      std::vector<int> found = ida.rootsFound();
      for (size_t r = 0; r < found.size(); ++r)
        if (found[r])
          *o.log << fmt::format("t = {:.10g}: event condition {} crossed "
                                "zero\n",
                                t, r + 1);
    }
    if (st.kind == StepStatus::StopReached || t >= s.stop ||
        (!o.everyStep && k > nOut))
      break;
    if (m.n_state_sets > 1) {
      cond = pivotConditions(ev, t, ida.y(), ida.yp());
      int best = chooseStateSet(cond, ida.set());
      if (best != ida.set() &&
          !switchStates(ev, ida, best, t, std::min(s.stop, t + s.interval),
                        cond, res, o.log))
        break;
    }
    progress.update(t);
  }
  progress.finish();
  return finish(&ida);
}

void printStats(const SimStats &st, std::ostream &out) {
  out << fmt::format("integrator                  {}\n", st.integrator)
      << fmt::format("unknowns                    {}\n", st.n)
      << fmt::format("linear solver               {}\n",
                     st.sparse ? "KLU (sparse)" : "dense LU")
      << fmt::format("steps                       {}\n", st.steps)
      << fmt::format("residual evaluations        {}\n", st.residualEvals)
      << fmt::format("jacobian evaluations        {}\n", st.jacobianEvals)
      << fmt::format("error test failures         {}\n", st.errorTestFailures)
      << fmt::format("nonlinear conv. failures    {}\n", st.convergenceFailures)
      << fmt::format("state set switches          {}\n", st.stateSwitches)
      << fmt::format("roots found                 {}\n", st.rootsFound)
      << fmt::format("largest drift residual      {:.3g}\n", st.maxDrift);
  if (st.projections > 0)
    out << fmt::format("constraint projections      {}\n", st.projections);
  out
      << fmt::format("initialization time         {:.6f} s\n", st.initTime)
      << fmt::format("wall time                   {:.6f} s\n", st.wallTime);
}

} // namespace ldae::runtime
