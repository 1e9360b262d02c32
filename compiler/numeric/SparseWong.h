// Wong sequences of a large sparse pencil (E, F) (seed 002) without dense
// n x n work: the pencil of a circuit has thousands of unknowns, and one
// dense decomposition of that size already takes seconds.
//
// The pencil is first reduced by strict equivalence, which the Wong
// sequences follow exactly:
//  1. index-1 pairs: a row whose E-part is zero and a column whose E-part
//     is zero with a nonzero F entry between them split off a 1 x 1 block
//     (0, f): it adds one dimension to T, none to V, and W-step 1 (the
//     algebraic unknowns of a circuit: resistor currents and the like);
//  2. row compression of E (row operations only): rows whose E-part is a
//     combination of others become constraints (a capacitor loop); a
//     column of E that only the pivot rows read (C (e_a - e_b)' in nodal
//     form) is cleared by a column operation with the pivot columns;
//  then 1 again on the new constraints. What is left is
//     [s E11 - F11, -F12; -F21, 0] with E11 square and nonsingular,
//  i.e. x' = A x + B z, 0 = C x with A = E11^-1 F11, B = E11^-1 F12,
//  C = F21, where z (multipliers) and the rows of C are few. Then
//     V: X_{i+1} = ker C ∩ A^-1(X_i + im B), carried by an orthonormal
//        basis of its annihilator (few rows),
//     T: Y_i = A(Y_{i-1} ∩ ker C) + im B, T_{i+1} = Y_i x R^m, carried by
//        a basis (few columns),
//  with A applied through one sparse LU of E11 (KLU). When the reduced
//  pencil is not of that form (E11 not square or numerically singular),
//  the dense Wong sequences run on the reduced pencil.
#pragma once

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace ldae::numeric {

/// A rows x cols pencil E x' = F x (+ inputs) as coordinate lists
/// (duplicates are summed).
struct SparsePencil {
  struct Entry {
    int row, col;
    double value;
  };
  int rows = 0, cols = 0;
  std::vector<Entry> E, F;
};

struct PencilOptions {
  /// Rank tolerance relative to the larger max-norm of E and F.
  double tol = 1e-10;
  /// Pencils with at most this many columns go straight to the dense
  /// Wong sequences (no reduction). 0 by default: the reduction decides
  /// ranks relative to each row (scale-free), the dense sequences relative
  /// to the norm of the whole pencil, which a capacitance of 1e-9 beside a
  /// resistance of 1e3 defeats.
  int denseLimit = 0;
  /// Largest reduced pencil the dense fallback accepts.
  int denseFallbackLimit = 1500;
};

/// What the Wong sequences say about a pencil.
struct PencilAnalysis {
  bool computed = false; ///< false: too large for the dense fallback
  bool square = false;
  bool regular = false;  ///< square and V ⊕ T = R^n
  int dimV = 0, dimW = 0;
  int stepsV = 0;        ///< steps until V_i was stationary
  int stepsW = 0;        ///< smallest i with W_i = W_{i+1} (index if regular)
  /// Basis (columns, over the pencil's columns) of V ∩ T: the directions a
  /// solution may move in freely (nonzero only when singular);
  /// orthonormal up to 400 directions, past that the reduction's own
  /// independent columns.
  Eigen::MatrixXd freeDirections;
  /// dim(V ∩ T): freeDirections.cols(), except where columns that no
  /// entry reads are free beyond kMaxUnitDirections of them (one equation
  /// for 10,000 unknowns: a dense basis of 9,999 directions took 2.4 GB),
  /// when freeDirections holds the first kMaxUnitDirections of them.
  Eigen::Index freeCount = 0;
  /// How it was computed: "dense", "structured" or "reduced-dense", and
  /// the size of the reduced pencil.
  std::string path;
  int reducedRows = 0, reducedCols = 0;
  int indexOnePairs = 0; ///< 1 x 1 blocks split off by step 1
};

/// Past this many columns that no entry of a pencil reads, only this many
/// of their unit directions are kept in PencilAnalysis::freeDirections.
inline constexpr Eigen::Index kMaxUnitDirections = 64;

/// The Wong sequences of `p` (see the file comment for the method).
PencilAnalysis analyzePencil(const SparsePencil &p,
                             const PencilOptions &opts = {});

/// The dense matrices of `p` (for small pencils and tests).
void densePencil(const SparsePencil &p, Eigen::MatrixXd &E,
                 Eigen::MatrixXd &F);

} // namespace ldae::numeric
