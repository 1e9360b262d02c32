// Causalization of the index-1 system (pass "causalize"): the residuals are
// matched to what the integrator does not own (the algebraic unknowns and the
// derivatives of the states) and put in BLT order; every algebraic unknown a
// block computes explicitly is substituted away, so the integrator sees the
// states and the iteration (tearing) variables only, and everything else is
// an expression of them, computed inside the residual and at output time.
//
// A scalar block linear in its variable becomes an assignment (its
// coefficient is the block's Jacobian: where it vanishes the block is
// singular, and the division it becomes reports a located domain error).
// Algebraic loops are torn: a few iteration variables are chosen (see
// docs/causalization.md for the heuristic) so that the other equations of
// the loop solve for one variable each with a coefficient that cannot
// vanish (a nonzero constant or a parameter expression); the rest stay
// residuals in the iteration variables.
#pragma once

#include "ir/DaeSystem.h"
#include "support/Diagnostics.h"

#include <string>
#include <vector>

namespace ldae::passes {

struct CausalizeOptions {
  /// false: the system is left as index reduction built it (`--causalize
  /// off`: every unknown goes to the integrator).
  bool enabled = true;
  /// Names the files of equation locations in the report (may be null).
  const SourceManager *sources = nullptr;
};

/// One block of the BLT order of state set 0.
struct CausalBlock {
  enum class Kind {
    Explicit,   // one algebraic unknown, computed by an assignment
    Derivative, // one state derivative: its residual stays (the integrator's)
    Nonlinear,  // one algebraic unknown the equation does not solve
                // explicitly: an iteration variable
    Kept,       // one algebraic unknown the equation could compute, kept
                // as the integrator's for `reason`
    Loop,       // several unknowns (an algebraic loop), torn
  };
  Kind kind = Kind::Explicit;
  std::vector<std::string> variables; // what the block determines
  std::vector<std::string> equations; // "file:line" of each equation
  /// Loops and nonlinear blocks: the unknowns left to the integrator (the
  /// tearing variables, and the state derivatives of the block).
  std::vector<std::string> iteration;
  /// Loops: the equations kept as residuals in the iteration variables.
  int residuals = 0;
  std::string reason; // Kept: why
};

const char *causalBlockKindName(CausalBlock::Kind k); // "explicit", ...

struct CausalResult {
  bool applied = false;
  std::vector<CausalBlock> blocks; // solve order
  int unknownsBefore = 0;          // the index-1 system's unknowns
  /// What the integrator owns: states (their derivatives through y') and
  /// iteration variables.
  std::vector<std::string> integratorUnknowns;
  int explicitCount = 0; // unknowns substituted away
  int tornLoops = 0;
  int iterationVariables = 0; // algebraic unknowns left to the integrator
  /// Every remaining unknown is a state and every state derivative is
  /// computed explicitly: the system is an ODE x' = f(t, x).
  bool ode = false;
};

/// Causalizes `sys` in place (all state sets alike). Never fails on a
/// valid index-1 system: what cannot be solved explicitly stays an unknown.
void causalize(ir::DaeSystem &sys, const CausalizeOptions &opts,
               CausalResult &out);

} // namespace ldae::passes
