// The assignment solver on matrices whose optimum is known by hand.

#include "dynamap/base/hungarian.h"

#include <gtest/gtest.h>

#include <limits>

namespace dynamap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(Hungarian, SquareMatrixTakesTheGlobalOptimumNotTheGreedyOne) {
  // Greedy would take (0,0)=1 and then (1,1)=10: total 11. The optimum is 2 + 3 = 5.
  Eigen::MatrixXd c(2, 2);
  c << 1, 2, 3, 10;
  EXPECT_EQ(solveAssignment(c, kInf), (std::vector<int>{1, 0}));
}

TEST(Hungarian, ThreeByThreeClassic) {
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3, 2, 0, 5, 3, 2, 2;  // optimum 1 + 2 + 2 = 5
  EXPECT_EQ(solveAssignment(c, kInf), (std::vector<int>{1, 0, 2}));
}

TEST(Hungarian, MoreRowsThanColumnsLeavesTheCostliestRowOut) {
  Eigen::MatrixXd c(3, 2);
  c << 1, 9, 9, 1, 5, 5;
  EXPECT_EQ(solveAssignment(c, kInf), (std::vector<int>{0, 1, -1}));
}

TEST(Hungarian, MoreColumnsThanRows) {
  Eigen::MatrixXd c(2, 4);
  c << 7, 3, 8, 1, 2, 6, 1, 9;
  EXPECT_EQ(solveAssignment(c, kInf), (std::vector<int>{3, 2}));
}

TEST(Hungarian, ForbiddenPairsAreNeverAssigned) {
  Eigen::MatrixXd c(2, 2);
  c << kInf, kInf, 1, 2;  // row 0 may take nothing
  EXPECT_EQ(solveAssignment(c, kInf), (std::vector<int>{-1, 0}));
  Eigen::MatrixXd d(2, 2);
  d << 0.5, 0.9, 0.4, 2.0;  // 2.0 is at the forbidden limit: row 1 must take column 0
  EXPECT_EQ(solveAssignment(d, 1.0), (std::vector<int>{1, 0}));
}

TEST(Hungarian, AsManyAllowedPairsAsPossibleBeforeTheCheapest) {
  // Row 0 alone would take column 0 (0.1), but then row 1 has nothing: both are matched.
  Eigen::MatrixXd c(2, 2);
  c << 0.1, 0.5, 0.2, kInf;
  EXPECT_EQ(solveAssignment(c, kInf), (std::vector<int>{1, 0}));
}

TEST(Hungarian, EmptyMatrices) {
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXd(0, 3), kInf).empty());
  EXPECT_EQ(solveAssignment(Eigen::MatrixXd(2, 0), kInf), (std::vector<int>{-1, -1}));
}

}  // namespace
}  // namespace dynamap
