// What every initialization path works from and hands back: the conditions
// it holds (InitConditions) and its outcome (InitOutcome). Apart from the
// paths themselves so that the dense one (ConsistentInit.h) can fall to the
// sparse one (SparseInit.h) without the two headers needing each other.
#pragma once

#include "ldae/model.h"

#include <string>
#include <vector>

namespace ldae::runtime {

/// What the (re-)initialization holds: the unknowns whose values are
/// conditions (fixed start values at the start, the targets of fired
/// reinits after an event) and whether the initial equations apply (only
/// at the start).
struct InitConditions {
  std::vector<char> held; ///< size n
  bool initialEquations = true;

  /// The start: fixed start values and initial equations.
  static InitConditions atStart(const ldae_model &m);
  /// After an event: the unknowns `held` (indices), no initial equations.
  static InitConditions afterEvent(const ldae_model &m,
                                   const std::vector<int> &held);
  bool isHeld(int i) const { return held[i] != 0; }
  int numInitial(const ldae_model &m) const {
    return initialEquations ? m.n_init : 0;
  }
};

struct InitOutcome {
  bool ok = false;
  std::vector<double> y, yp;
  int jumpDim = 0;           ///< dim T at the start point (after fixing)
  int index = 0;             ///< Wong steps of T (the index of the pencil)
  bool nearestPoint = false; ///< fell back to the nominal-scaled nearest point
  double residual = 0;       ///< smallest max |residual| reached
  std::string failure;       ///< when !ok: which equations cannot be met
  int domainRow = -1;        ///< when !ok: residual row of a domain error
  std::vector<double> domainY; ///< the unknowns at that domain error
  /// False when the method does not apply to the model (see SparseInit.h);
  /// `failure` then says why.
  bool applicable = true;
  int moved = 0; ///< sparse path: differential values the conditions move
                 ///< (fixed ones not counted)
  int kept = 0;  ///< sparse path: differential values kept at their start
  int projected = 0; ///< sparse path: in minimum-norm blocks
  bool written = false; ///< dense path: T of the model as written was used
  int jumped = 0; ///< unknowns (not derivatives) that moved (reinitialize-
                  ///< AfterEvent; beyond round-off, as reportMoves)
};

} // namespace ldae::runtime
