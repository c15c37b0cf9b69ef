#include "dynamap/base/hungarian.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynamap {

namespace {

// The e-maxx formulation with potentials u, v on an n x m matrix with n <= m (1-based inside):
// rows are added one by one, each by a shortest augmenting path. Returns row -> column.
std::vector<int> solveWide(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows()), m = static_cast<int>(a.cols());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(m + 1, 0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j) {
    if (p[j] != 0) row_to_col[p[j] - 1] = j - 1;
  }
  return row_to_col;
}

}  // namespace

std::vector<int> solveAssignment(const Eigen::MatrixXd& cost, double forbidden) {
  const Eigen::Index rows = cost.rows(), cols = cost.cols();
  std::vector<int> out(static_cast<std::size_t>(rows), -1);
  if (rows == 0 || cols == 0) return out;
  // Forbidden pairs cost more than every allowed assignment together: the solver then uses as
  // few of them as it can, and those it must use are dropped afterwards.
  double total = 0;
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      const double c = cost(i, j);
      if (std::isfinite(c) && c < forbidden) total += std::abs(c);
    }
  }
  const double big = 2 * total + 1;
  Eigen::MatrixXd a(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      const double c = cost(i, j);
      a(i, j) = std::isfinite(c) && c < forbidden ? c : big;
    }
  }
  const bool wide = rows <= cols;
  const std::vector<int> solved = solveWide(wide ? a : Eigen::MatrixXd(a.transpose()));
  for (std::size_t k = 0; k < solved.size(); ++k) {
    const int other = solved[k];
    if (other < 0) continue;
    const int r = wide ? static_cast<int>(k) : other, c = wide ? other : static_cast<int>(k);
    if (a(r, c) < big) out[static_cast<std::size_t>(r)] = c;
  }
  return out;
}

}  // namespace dynamap
