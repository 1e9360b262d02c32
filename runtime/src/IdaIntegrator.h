// A thin owner of one IDA integrator for an ldae_model: SUNContext, serial
// vectors, tolerances scaled by the nominal values, the differential/
// algebraic id of the current state set with the algebraic variables kept
// out of the error test, the dense or KLU linear solver with the model's
// Jacobian, root functions. Re-initialized in place when the state set
// changes; counters are summed across re-initializations.
#pragma once

#include "ModelEval.h"
#include "ldae/Simulation.h"

#include <memory>
#include <string>
#include <vector>

namespace ldae::runtime {

class IdaIntegrator {
public:
  explicit IdaIntegrator(const ModelEval &ev);
  ~IdaIntegrator();
  IdaIntegrator(const IdaIntegrator &) = delete;
  IdaIntegrator &operator=(const IdaIntegrator &) = delete;

  /// Creates the integrator at (t0, y, y') for state set `set`; `atol` per
  /// unknown. Errors are internal (a SUNDIALS call failed).
  Expected<bool> init(int set, double t0, const double *y, const double *yp,
                      double rtol, const std::vector<double> &atol,
                      double tstop, bool suppressAlg = true);
  /// Restarts at (t, y, y') with state set `set` (new residual, id vector,
  /// Jacobian; the KLU solver is rebuilt for the new pattern).
  Expected<bool> reinit(int set, double t, const double *y, const double *yp);
  /// IDACalcIC(IDA_YA_YDP_INIT): y' of differential and y of algebraic
  /// unknowns from the differential y. Returns the IDA flag; on success the
  /// vectors hold the consistent point.
  int calcIC(double tout1);
  /// Sets the time the next steps must stop at exactly (an output time).
  Expected<bool> setStopTime(double tstop);
  /// One internal step towards the stop time (IDA_ONE_STEP). Returns the
  /// IDA flag (>= 0 ok: success, tstop reached, root found).
  int step(double &tret);
  /// k-th derivative of the interpolating polynomial at t (within the last
  /// step) into out.
  Expected<bool> dky(double t, int k, double *out);
  /// The current solution vectors (after step or calcIC).
  const double *y() const;
  const double *yp() const;
  int set() const { return data_.set; }
  bool sparse() const { return sparse_; }

  /// Adds this integrator's counters (all restarts) into `stats`.
  void addCounters(SimStats &stats) const;
  /// Root components that were found at the last IDA_ROOT_RETURN.
  std::vector<int> rootsFound() const;

  /// Weighted local error of each unknown at the last (failed) step.
  std::vector<double> weightedErrors() const;
  /// Time IDA reached.
  double currentTime() const;
  /// Size of the last successful step.
  double lastStep() const;
  /// The iteration-matrix coefficient of the last step.
  double currentCj() const;
  /// Residual row of the last domain error (-1: none).
  int lastDomainRow() const { return data_.domainRow; }
  /// The unknowns at that domain error (null: none).
  const double *lastDomainY() const {
    return data_.domainY.empty() ? nullptr : data_.domainY.data();
  }
  /// The last message IDA wanted to print (we silence IDA's printing).
  const std::string &idaMessage() const { return data_.idaMessage; }

  /// State shared with the C callbacks.
  struct CallbackData {
    const ModelEval *ev = nullptr;
    int set = 0;
    int domainRow = -1;
    std::vector<double> domainY; // y where the domain error happened
    std::string idaMessage;
  };

private:
  Expected<bool> setupLinearSolver();
  Expected<bool> setupId();

  const ModelEval &ev_;
  CallbackData data_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool sparse_ = false;
  SimStats saved_; // counters of earlier restarts
};

} // namespace ldae::runtime
