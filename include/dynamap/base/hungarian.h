#pragma once
// Minimum-cost assignment (the Hungarian method, Kuhn-Munkres with potentials, O(n^2 m)).

#include <Eigen/Core>
#include <vector>

namespace dynamap {

/// For each row of `cost` (rows x cols, any shape), the column assigned to it, or -1. Each
/// column is used at most once and the sum of the assigned costs is minimal among assignments
/// of min(rows, cols) pairs. Entries that are not finite (or >= `forbidden`) are never
/// assigned: a row whose best assignment would need one is left at -1. Deterministic.
std::vector<int> solveAssignment(const Eigen::MatrixXd& cost, double forbidden);

}  // namespace dynamap
