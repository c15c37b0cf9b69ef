#include "dynamap/localization/field_matcher.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>

namespace dynamap {
namespace {

/// Cells of a field, each counted `w` times (or once, `w` empty).
struct Cells {
  std::vector<int> x, y, w;
};

/// The points' cells seen from `pose`, one per point.
void pointCells(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                const mrpt::poses::CPose2D& pose, Cells& cells) {
  cells.x.resize(pts.size());
  cells.y.resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const mrpt::math::TPoint2D g = pose + pts[i];
    cells.x[i] = field.cellX(g.x);
    cells.y[i] = field.cellY(g.y);
  }
}

/// Each distinct cell of `all` once, counted as often as it occurs there.
Cells distinctCells(const Cells& all) {
  std::vector<std::pair<int, int>> yx(all.x.size());
  for (std::size_t i = 0; i < yx.size(); ++i) yx[i] = {all.y[i], all.x[i]};
  std::sort(yx.begin(), yx.end());
  Cells distinct;
  for (std::size_t i = 0; i < yx.size(); ++i) {
    if (i > 0 && yx[i] == yx[i - 1]) {
      ++distinct.w.back();
      continue;
    }
    distinct.x.push_back(yx[i].second);
    distinct.y.push_back(yx[i].first);
    distinct.w.push_back(1);
  }
  return distinct;
}

/// For each of the nx x ny offsets (x0 + step bx, y0 + step by), row by row, the sum of `read`
/// over `cells` so offset, each cell counted its `w` times. The cells are added in their order,
/// so a sum of doubles over every point is the one taken point by point. Sums of a coarse level
/// are integers (its units; bounds, needed only in order), the same over merged cells as over
/// every point.
template <typename T, typename Read>
void latticeSums(const Cells& cells, int x0, int y0, int step, int nx, int ny, Read read,
                 std::vector<T>& sums) {
  sums.assign(static_cast<std::size_t>(nx) * ny, T{0});
  const std::size_t n = cells.x.size();
  for (int by = 0; by < ny; ++by) {
    for (int bx = 0; bx < nx; ++bx) {
      const int dx = x0 + bx * step, dy = y0 + by * step;
      T s{0};
      if (cells.w.empty()) {
        for (std::size_t i = 0; i < n; ++i) s += read(cells.x[i] + dx, cells.y[i] + dy);
      } else {
        for (std::size_t i = 0; i < n; ++i)
          s += cells.w[i] * read(cells.x[i] + dx, cells.y[i] + dy);
      }
      sums[static_cast<std::size_t>(by) * nx + bx] = s;
    }
  }
}

/// Cost and gradient terms of the points at `pose`: sum (1 - f)^2, J^T r and J^T J.
double pointTerms(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                  const mrpt::poses::CPose2D& pose, Eigen::Vector3d& g, Eigen::Matrix3d& h) {
  g.setZero();
  h.setZero();
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  double cost = 0;
  for (const auto& p : pts) {
    const double rx = c * p.x - s * p.y, ry = s * p.x + c * p.y;  // the point, rotated
    double fx, fy;
    const double f = field.interpolate(pose.x() + rx, pose.y() + ry, fx, fy);
    const double r = 1.0 - f;
    const Eigen::Vector3d j(-fx, -fy, -(fx * -ry + fy * rx));
    cost += r * r;
    g += j * r;
    h += j * j.transpose();
  }
  return cost;
}

}  // namespace

namespace {

// The poses of a window search that score at least `ratio` times the best (the best among
// them), as offsets from the guess in cells and angle steps: branch and bound over the field's
// two coarse levels, blocks in order of their bound until none can come near the best, or reach
// `floor` (a sum of field values: a caller who refuses any score below it).
struct Candidate {
  double sum;
  int turn, dx, dy;
};

/// A block of offsets in the branch and bound: `side` x `side` cells from (dx, dy) at `turn`,
/// none scoring above `bound` units.
struct Block {
  int bound;
  int side, turn, dx, dy;
  /// The heap's order, top first: the highest bound; of equal bounds a coarser block, then the
  /// smaller (turn, dx, dy). So every block of the finer level is taken in the order of a sort
  /// of them all by (-bound, turn, dx, dy), though most are never scored.
  bool operator<(const Block& o) const {
    return std::tie(bound, side, o.turn, o.dx, o.dy) < std::tie(o.bound, o.side, turn, dx, dy);
  }
};

/// The cells of a window search's points at each of its headings (index turn + turns), and
/// those its bounds are summed over: the same merged where that pays (`merged` non-empty).
struct Headings {
  std::vector<Cells> points, merged;
  const Cells& boundCells(int i) const { return merged.empty() ? points[i] : merged[i]; }
};

/// Every K2 x K2 block of offsets within `shift` cells at every heading within `turns` steps,
/// with its coarser level's bound; `h` gets the points' cells at each heading.
std::vector<Block> topLevel(const LikelihoodField& field,
                            const std::vector<mrpt::math::TPoint2D>& pts,
                            const mrpt::poses::CPose2D& guess, int shift, int turns,
                            double step_rad, Headings& h) {
  constexpr int K2 = LikelihoodField::kCoarser;
  const int side = 2 * shift / K2 + 1;  // coarser blocks per side of the window
  h.points.assign(2 * turns + 1, {});
  // Merged cells pay where a heading has more blocks than there are points, as searching a
  // whole map has (its coarse cells hold several points each); elsewhere sorting costs more
  // than it saves.
  h.merged.assign(static_cast<std::size_t>(side) * side > pts.size() ? 2 * turns + 1 : 0, {});
  std::vector<Block> blocks;
  blocks.reserve(static_cast<std::size_t>(side) * side * (2 * turns + 1));
  std::vector<int> units;
  for (int t = -turns, i = 0; t <= turns; ++t, ++i) {
    const mrpt::poses::CPose2D at(guess.x(), guess.y(), guess.phi() + t * step_rad);
    pointCells(field, pts, at, h.points[i]);
    if (!h.merged.empty()) h.merged[i] = distinctCells(h.points[i]);
    latticeSums(
        h.boundCells(i), -shift, -shift, K2, side, side,
        [&](int x, int y) { return field.coarserUnits(x, y); }, units);
    for (int k = 0; k < side * side; ++k)
      blocks.push_back({units[k], K2, t, k % side * K2 - shift, k / side * K2 - shift});
  }
  return blocks;
}

std::vector<Candidate> searchNearBest(const LikelihoodField& field,
                                      const std::vector<mrpt::math::TPoint2D>& pts,
                                      const mrpt::poses::CPose2D& guess, double window_m,
                                      double window_rad, double step_rad, double ratio,
                                      double floor = 0) {
  constexpr int K = LikelihoodField::kCoarse, K2 = LikelihoodField::kCoarser;
  const int shift = static_cast<int>(std::floor(window_m / field.resolution() + 1e-9));
  const int turns = step_rad > 0 ? static_cast<int>(std::floor(window_rad / step_rad + 1e-9)) : 0;
  // Best first over both levels: every block of K2 x K2 offsets at every angle, by the coarser
  // level's bound; a block taken from the heap is split into its K x K blocks (the coarse
  // level's bound), and those into their offsets. A child's bound is no higher than its
  // parent's, so the K x K blocks are scored in the order of their bounds, as if all had been.
  Headings h;
  std::priority_queue<Block> heap(std::less<Block>(),
                                  topLevel(field, pts, guess, shift, turns, step_rad, h));
  std::vector<Candidate> good;
  std::vector<int> units;
  std::vector<double> sums;
  double top = 0;
  // Until no block can beat the best (or come near it: the runner-up must be found too).
  const auto open = [&](const Block& b) {
    const double bound = b.bound * LikelihoodField::kUnit;
    return bound > ratio * top && bound >= floor;
  };
  while (!heap.empty() && open(heap.top())) {
    const Block b = heap.top();
    heap.pop();
    const int i = b.turn + turns;
    const int step = b.side == K2 ? K : 1, n = b.side / step;  // a child's side; per side
    const int nx = std::min(n, (shift - b.dx) / step + 1);
    const int ny = std::min(n, (shift - b.dy) / step + 1);
    if (b.side == K2) {
      latticeSums(
          h.boundCells(i), b.dx, b.dy, step, nx, ny,
          [&](int x, int y) { return field.coarseUnits(x, y); }, units);
      for (int k = 0; k < nx * ny; ++k)
        heap.push({units[k], K, b.turn, b.dx + k % nx * K, b.dy + k / nx * K});
      continue;
    }
    latticeSums(
        h.points[i], b.dx, b.dy, step, nx, ny, [&](int x, int y) { return field.cell(x, y); },
        sums);
    for (int k = 0; k < nx * ny; ++k) {
      if (sums[k] < ratio * top) continue;
      good.push_back({sums[k], b.turn, b.dx + k % nx, b.dy + k / nx});
      top = std::max(top, sums[k]);
    }
  }
  return good;
}

}  // namespace

FieldMatch searchWide(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                      const mrpt::poses::CPose2D& guess, double window_m, double window_rad,
                      double step_rad, double separation_m, double ambiguity_ratio,
                      double min_score) {
  FieldMatch best;
  best.pose = guess;
  if (pts.empty() || field.empty()) return best;
  const double res = field.resolution();
  const double n = static_cast<double>(pts.size());
  // Below ratio x min_score no pose can be the best one accepted nor its runner-up.
  const std::vector<Candidate> good =
      searchNearBest(field, pts, guess, window_m, window_rad, step_rad, ambiguity_ratio,
                     ambiguity_ratio * min_score * n);
  int bt = 0, bx = 0, by = 0;
  double bs = -1;
  for (const auto& [s, t, dx, dy] : good) {
    if (s > bs) bs = s, bt = t, bx = dx, by = dy;
  }
  if (bs < 0) return best;
  best.score = bs / n;
  best.pose = {guess.x() + bx * res, guess.y() + by * res, guess.phi() + bt * step_rad};
  const double sep_cells = separation_m / res, sep_turns = (5.0 * M_PI / 180.0) / step_rad;
  for (const auto& [s, t, dx, dy] : good) {
    const bool far = std::hypot(dx - bx, dy - by) > sep_cells || std::abs(t - bt) > sep_turns;
    if (far && s / n > best.runner_up) {
      best.runner_up = s / n;
      best.runner_up_pose = {guess.x() + dx * res, guess.y() + dy * res,
                             guess.phi() + t * step_rad};
    }
  }
  return best;
}

std::vector<FieldMatch> searchPlaces(const LikelihoodField& field,
                                     const std::vector<mrpt::math::TPoint2D>& pts,
                                     const mrpt::poses::CPose2D& guess, double window_m,
                                     double window_rad, double step_rad, double separation_m,
                                     double ratio, std::size_t max_places) {
  std::vector<FieldMatch> places;
  if (pts.empty() || field.empty()) return places;
  std::vector<Candidate> good =
      searchNearBest(field, pts, guess, window_m, window_rad, step_rad, ratio);
  // Best first; ties in the order searched.
  std::stable_sort(good.begin(), good.end(),
                   [](const Candidate& a, const Candidate& b) { return a.sum > b.sum; });
  const double res = field.resolution(), n = static_cast<double>(pts.size());
  const double sep_cells = separation_m / res, sep_rad = 5.0 * M_PI / 180.0;
  std::vector<const Candidate*> kept;
  for (const Candidate& c : good) {
    if (c.sum < ratio * good.front().sum || kept.size() == max_places) break;
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const Candidate* k) {
      // Headings round the circle: a window of +-180 degrees holds the half turn twice.
      const double turn = mrpt::math::wrapToPi((c.turn - k->turn) * step_rad);
      return std::hypot(c.dx - k->dx, c.dy - k->dy) <= sep_cells && std::abs(turn) <= sep_rad;
    });
    if (near) continue;
    kept.push_back(&c);
    FieldMatch m;
    m.pose = {guess.x() + c.dx * res, guess.y() + c.dy * res, guess.phi() + c.turn * step_rad};
    m.score = c.sum / n;
    places.push_back(m);
  }
  return places;
}

FieldMatch refine(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                  const mrpt::poses::CPose2D& start, const mrpt::poses::CPose2D& prior,
                  double translation_weight, double rotation_weight, int max_iterations) {
  auto total = [&](const mrpt::poses::CPose2D& p, Eigen::Vector3d& g, Eigen::Matrix3d& h) {
    double cost = pointTerms(field, pts, p, g, h);
    const double wt = translation_weight * translation_weight,
                 wr = rotation_weight * rotation_weight;
    const Eigen::Vector3d d(p.x() - prior.x(), p.y() - prior.y(),
                            mrpt::math::wrapToPi(p.phi() - prior.phi()));
    const Eigen::Vector3d w(wt, wt, wr);
    cost += d.dot(w.cwiseProduct(d));
    g += w.cwiseProduct(d);
    h.diagonal() += w;
    return cost;
  };
  FieldMatch m;
  m.pose = start;
  if (pts.empty() || field.empty()) return m;
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  double cost = total(m.pose, g, h), lambda = 1e-3;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Matrix3d a = h;
    a.diagonal() *= 1.0 + lambda;
    const Eigen::Vector3d step = a.ldlt().solve(-g);
    if (!step.allFinite()) break;
    const mrpt::poses::CPose2D next(m.pose.x() + step.x(), m.pose.y() + step.y(),
                                    mrpt::math::wrapToPi(m.pose.phi() + step.z()));
    Eigen::Vector3d g2;
    Eigen::Matrix3d h2;
    const double c2 = total(next, g2, h2);
    if (c2 < cost) {
      m.pose = next, cost = c2, g = g2, h = h2, lambda *= 0.1;
      if (step.head<2>().norm() < 1e-5 && std::abs(step.z()) < 1e-6) break;
    } else {
      lambda *= 10;
      if (lambda > 1e6) break;
    }
  }
  Eigen::Vector3d gp;
  pointTerms(field, pts, m.pose, gp, m.information);
  double gx, gy, sum = 0;
  const double c = std::cos(m.pose.phi()), s = std::sin(m.pose.phi());
  for (const auto& p : pts) {
    sum +=
        field.interpolate(m.pose.x() + c * p.x - s * p.y, m.pose.y() + s * p.x + c * p.y, gx, gy);
  }
  m.score = sum / static_cast<double>(pts.size());
  return m;
}

}  // namespace dynamap
