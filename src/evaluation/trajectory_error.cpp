#include "dynamap/evaluation/evaluation.h"
// The trajectory level of the evaluation: anchored and aligned position errors, relative errors.

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamap/base/angles.h"

namespace dynamap {

const TimedPose* poseAtTime(const std::vector<TimedPose>& poses, double t, double tolerance) {
  auto it = std::lower_bound(poses.begin(), poses.end(), t - tolerance,
                             [](const TimedPose& p, double v) { return p.t < v; });
  const TimedPose* best = nullptr;
  for (; it != poses.end() && it->t <= t + tolerance; ++it) {
    if (!best || std::abs(it->t - t) < std::abs(best->t - t)) best = &*it;
  }
  return best;
}

TrajectoryError trajectoryError(const std::vector<TimedPose>& estimate,
                                const std::vector<TimedPose>& truth, double time_tolerance_s) {
  TrajectoryError e;
  bool anchored = false;
  double c = 1, s = 0, tx = 0, ty = 0, dphi = 0;  // estimate frame -> truth frame
  double sum_xy = 0, sum_phi = 0;
  for (const TimedPose& p : estimate) {
    const TimedPose* g = poseAtTime(truth, p.t, time_tolerance_s);
    if (!g) {
      ++e.unmatched;
      continue;
    }
    if (!anchored) {  // the rotation and translation that put this pose on the truth's
      dphi = wrapAngle(g->phi - p.phi);
      c = std::cos(dphi), s = std::sin(dphi);
      tx = g->x - (c * p.x - s * p.y);
      ty = g->y - (s * p.x + c * p.y);
      anchored = true;
    }
    const double x = c * p.x - s * p.y + tx, y = s * p.x + c * p.y + ty;
    const double d2 = (x - g->x) * (x - g->x) + (y - g->y) * (y - g->y);
    const double dp = wrapAngle(p.phi + dphi - g->phi);
    sum_xy += d2;
    sum_phi += dp * dp;
    e.max_xy_m = std::max(e.max_xy_m, std::sqrt(d2));
    ++e.matched;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  e.rmse_xy_m = e.matched ? std::sqrt(sum_xy / static_cast<double>(e.matched)) : nan;
  e.rmse_phi_rad = e.matched ? std::sqrt(sum_phi / static_cast<double>(e.matched)) : nan;
  if (!e.matched) e.max_xy_m = nan;
  return e;
}

namespace {

/// The closed-form rotation and translation putting `est`'s positions onto `gt`'s (least
/// squares), and the RMSE after it.
double alignedRmse(const std::vector<TimedPose>& est, const std::vector<TimedPose>& gt) {
  const double n = static_cast<double>(est.size());
  double ex = 0, ey = 0, gx = 0, gy = 0;
  for (std::size_t i = 0; i < est.size(); ++i)
    ex += est[i].x, ey += est[i].y, gx += gt[i].x, gy += gt[i].y;
  ex /= n, ey /= n, gx /= n, gy /= n;
  double sxx = 0, sxy = 0;  // sum of dot and cross products of the centred positions
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double ax = est[i].x - ex, ay = est[i].y - ey, bx = gt[i].x - gx, by = gt[i].y - gy;
    sxx += ax * bx + ay * by;
    sxy += ax * by - ay * bx;
  }
  const double th = std::atan2(sxy, sxx), c = std::cos(th), s = std::sin(th);
  double sum = 0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double ax = est[i].x - ex, ay = est[i].y - ey;
    const double dx = c * ax - s * ay + gx - gt[i].x, dy = s * ax + c * ay + gy - gt[i].y;
    sum += dx * dx + dy * dy;
  }
  return std::sqrt(sum / n);
}

/// The motion from a to b in a's frame.
TimedPose relative(const TimedPose& a, const TimedPose& b) {
  const double c = std::cos(a.phi), s = std::sin(a.phi), dx = b.x - a.x, dy = b.y - a.y;
  return {0, c * dx + s * dy, -s * dx + c * dy, wrapAngle(b.phi - a.phi)};
}

/// Mean relative error over pairs `delta` metres of the truth's path apart (each pose i with
/// the first j whose path from i reaches delta).
void relativeError(const std::vector<TimedPose>& est, const std::vector<TimedPose>& gt,
                   double delta, double& xy, double& phi) {
  std::vector<double> path(gt.size(), 0.0);
  for (std::size_t i = 1; i < gt.size(); ++i) {
    path[i] = path[i - 1] + std::hypot(gt[i].x - gt[i - 1].x, gt[i].y - gt[i - 1].y);
  }
  double sum_xy = 0, sum_phi = 0;
  std::size_t pairs = 0, j = 0;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    j = std::max(j, i);
    while (j < gt.size() && path[j] - path[i] < delta) ++j;
    if (j >= gt.size()) break;
    const TimedPose e = relative(est[i], est[j]), g = relative(gt[i], gt[j]);
    sum_xy += std::hypot(e.x - g.x, e.y - g.y);
    sum_phi += std::abs(wrapAngle(e.phi - g.phi));
    ++pairs;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  xy = pairs ? sum_xy / static_cast<double>(pairs) : nan;
  phi = pairs ? sum_phi / static_cast<double>(pairs) : nan;
}

}  // namespace

AlignedTrajectoryError alignedTrajectoryError(const std::vector<TimedPose>& estimate,
                                              const std::vector<TimedPose>& truth,
                                              double time_tolerance_s) {
  std::vector<TimedPose> est, gt;
  for (const TimedPose& p : estimate) {
    const TimedPose* g = poseAtTime(truth, p.t, time_tolerance_s);
    if (!g) continue;
    est.push_back(p);
    gt.push_back(*g);
  }
  AlignedTrajectoryError e;
  e.matched = est.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  e.aligned_rmse_xy_m = est.empty() ? nan : alignedRmse(est, gt);
  relativeError(est, gt, 1.0, e.rel_1m_xy_m, e.rel_1m_phi_rad);
  relativeError(est, gt, 10.0, e.rel_10m_xy_m, e.rel_10m_phi_rad);
  return e;
}

}  // namespace dynamap
