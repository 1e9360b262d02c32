// The Stabilization General Algorithm (seed 000 §3, Muñoz-Lecanda and
// Román-Roy; its time-dependent form, seed 001 §3-4, Gràcia and Martín) on
// a flat model: the model written as A(t, x) x' = alpha(t, x), constraints
// from the rows whose A-part vanishes on the current manifold, each new
// constraint's tangency row appended, until no new constraint appears.
// Ranks and "vanishes on the manifold" are decided numerically at several
// points of the current manifold near the start values (random tangent
// moves of a point reached from them); the constraints are
// built symbolically by Gaussian elimination with the pivots so chosen.
// Internal to compiler/passes; the "sga" pass reports it, "sga-system"
// builds the vector field on P_f from it.
#pragma once

#include "passes/Pipeline.h"
#include "passes/Results.h"

#include <string>
#include <vector>

namespace ldae::passes {

/// The model in the SGA's form. The coordinates x are the slots: each
/// unknown and its derivatives below its top order (an unknown written
/// with der(der(v)) has slots v and der(v); the identity der(slot k) =
/// slot k+1 is kept implicit). The rows are linear in the columns: the
/// top derivative of each unknown (der(v) of an algebraic v). An equation
/// nonlinear in a derivative gets that derivative as a slot (w = x', so
/// that it is linear in w').
struct SgaForm {
  std::vector<ir::VarKey> slots;
  std::vector<ir::VarKey> columns; // columns[j] differentiates unknown j
  std::vector<unsigned> top;       // per unknown j: the order of columns[j]
};

/// A row F(t, x, D) = 0 linear in the columns D: a model equation or the
/// tangency row d/dt phi of a constraint.
struct SgaRow {
  ir::ExprRef residual = nullptr;
  std::vector<int> sources; // indices into model.equations, sorted
  int constraint = -1;      // tangency row of constraints[constraint]
};

struct SgaConstraintExpr {
  ir::ExprRef expr = nullptr; // over time and the slots
  std::vector<int> sources;   // indices into model.equations, sorted
  int generation = 0;         // 0: primary
};

struct SgaResult {
  /// What the SGA ran on: the model as written (before alias elimination,
  /// whose substitutions would hide constraints the papers count), as
  /// unknowns, equations and highest orders; merged/matching unused.
  MatchingResult input;
  bool ran = false;
  std::string skipped; // why it did not run (e.g. the model's size)
  SgaReport::Outcome outcome = SgaReport::Outcome::Unique;
  SgaForm form;
  std::vector<SgaConstraintExpr> constraints; // every generation, in order
  int generations = 0;
  std::vector<SgaRow> rows; // the equations, then every tangency row
  /// Rows whose A-parts are independent on P_f (rank of A there): with
  /// the implicit chain identities they determine x' on P_f when the
  /// outcome is unique.
  std::vector<int> pivotRows;
  std::vector<int> redundant; // model equations implied by the others
  /// Equations written out that the others imply after differentiation
  /// (a hidden constraint made explicit): redundant too, but kept, the
  /// model then over-determined (the SGA's vector field runs it).
  std::vector<int> implied;
  int conflict = -1;          // no_solution: the constraint that cannot hold
  std::vector<int> freeColumns; // columns in the kernel of A on P_f
  int dof = 0;                // dim P_f (slots minus constraints)
  int freeFunctions = 0;
  int steps = 0;
  std::vector<double> point; // slots at a point of P_f
  /// Slots at the start values, each unknown without one computed from
  /// the equation that defines it (`lang = sqrt(...)`): the guesses
  /// initialization starts from (an auxiliary guessed as 0 can be outside
  /// its equations' domain: `force = .../lang`).
  std::vector<double> startGuess;
};

/// Largest number of slots the SGA runs on inside the dd pipeline's
/// cross-check: bench/run_sga.py measures 0.28 s at 125 coordinates, 1.7 s
/// at 250 (a pendulum chain), hundreds of times structural reduction.
inline constexpr size_t kSgaCrossCheckLimit = 150;

/// The unknowns (continuous variables), equations and highest orders of
/// the model as it stands.
MatchingResult sgaInput(const ir::Model &model);

/// Runs the SGA on `out.input`, filling `out`.
void runSga(PassContext &ctx, SgaResult &out);

/// The vector field on P_f as the system the runtime integrates
/// (SgaSystem.cpp): projecting onto the constraints (sga) or not (ode).
/// False after reporting why it cannot be built.
bool buildSgaSystem(PassContext &ctx, const SgaResult &sga, bool project,
                    ir::DaeSystem &out);

} // namespace ldae::passes
