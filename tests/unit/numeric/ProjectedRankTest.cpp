// The rank decision of a prolongation–projection step on Jacobians whose
// projection is known by hand (numeric/ProjectedRank.h).
#include "numeric/ProjectedRank.h"

#include <gtest/gtest.h>

using namespace ldae::numeric;
using Eigen::MatrixXd;

// Columns (x, x', x''): x' - v = 0 prolonged once, with v given; the row
// x'' - v' holds the high coordinate x'' alone, so nothing projects: the
// codimension in J_1 (x, x') is 1.
TEST(ProjectedRank, AHighCoordinateAloneProjectsNothing) {
  MatrixXd j(2, 3);
  j << 0, 1, 0, //
      0, 0, 1;
  ProjectedRank r = projectedRank(j, 2);
  EXPECT_EQ(r.total, 2);
  EXPECT_EQ(r.high, 1);
  EXPECT_EQ(r.projected(), 1);
}

// Two rows with the same high part (y'' + x and y'' - x, columns x, x', y,
// y', y''): their difference 2x is an equation of order 0 (the projection
// finds it), so the codimension in J_1 is 1 though no row is of order <= 1.
TEST(ProjectedRank, EqualHighPartsCancel) {
  MatrixXd j(2, 5);
  j << 1, 0, 0, 0, 1, //
      -1, 0, 0, 0, 1;
  ProjectedRank r = projectedRank(j, 4);
  EXPECT_EQ(r.total, 2);
  EXPECT_EQ(r.high, 1);
  EXPECT_EQ(r.projected(), 1);
}

// Rows of very different sizes (a prolonged equation's coefficients grow
// with each derivative) keep their rank once equilibrated, and a
// dependency perturbed at rounding level counts as one.
TEST(ProjectedRank, ScaledRowsAndRoundingLevelDependencies) {
  MatrixXd j(3, 3);
  j << 1e6, 2e6, 0,          //
      1e-3, 0, 1e-3,         //
      1, 2 * (1 + 1e-15), 0; // the first row, scaled, up to rounding
  ProjectedRank r = projectedRank(j, 3);
  EXPECT_EQ(r.total, 2);
  EXPECT_EQ(r.high, 0);
  EXPECT_EQ(r.projected(), 2);
  EXPECT_GT(r.smallestKept, 1e-2);
  EXPECT_LT(r.largestDropped, 1e-12);
}
