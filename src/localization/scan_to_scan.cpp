#include "dynamap/localization/scan_to_scan.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pose_constraint.h"

namespace dynamap {
namespace {

constexpr double kSearchRad = 0.05;   // a point looks at the earlier beams within this bearing
constexpr int kCoarseIterations = 8;  // iterations with the wide pairing gate

/// [m] how far a point at `range` may lie from its partner: `coarse` (wide) while the guess's
/// heading error (up to a degree, 1.4 m at 80 m) is being taken out, then tight.
double pairingGate(double range, bool coarse) {
  return coarse ? 0.3 + 0.02 * range : 0.1 + 0.01 * range;
}

/// [m] a point within this of its segment is an inlier, and the Cauchy kernel's scale.
double inlierDistance(double range) {
  return 0.05 + 0.005 * range;
}

/// What pair() needs of the earlier scan beyond its returns, worked out once per match instead
/// of once per point and iteration (a match pairs each point up to 30 times).
struct Beams {
  explicit Beams(const ScanReturns& returns)
      : e(returns),
        // The values CPose2D::inverseComposePoint reads, so the bearings come out the same.
        sx(returns.sensor.x()),
        sy(returns.sensor.y()),
        cos(returns.sensor.phi_cos()),
        sin(returns.sensor.phi_sin()),
        size(static_cast<int>(returns.point.size())),
        reach(std::max(3, static_cast<int>(std::ceil(kSearchRad / std::abs(returns.step))))),
        nan_if_none(returns.point) {
    // A beam without a return lies nowhere: its distance to every point is NaN, which is never
    // the nearest, so the search needs no branch on `valid` (mispredicted at every gap).
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < size; ++i) {
      if (!returns.valid[i]) nan_if_none[i] = {nan, nan};
    }
  }
  const ScanReturns& e;
  double sx, sy, cos, sin;
  int size, reach;  // beams, and how many a point looks at on either side of its bearing's
  std::vector<Eigen::Vector2d> nan_if_none;  // e.point, NaN where a beam has no return
};

/// std::lround(at) for |at| < 2^31, without the library call: at minus its truncation is exact.
int roundHalfAway(double at) {
  int r = static_cast<int>(at);
  const double f = at - r;
  if (f >= 0.5) ++r;
  if (f <= -0.5) --r;
  return r;
}

/// The segment a point `g` (in the earlier scan's robot frame) lies on: the nearest return of
/// the earlier scan within kSearchRad of g's bearing (no farther than `gate`), and the
/// neighbouring beam's return on the same surface nearer to g. False when there is none.
bool pair(const Beams& b, const Eigen::Vector2d& g, double gate, Eigen::Vector2d& q,
          Eigen::Vector2d& n) {
  const ScanReturns& e = b.e;
  // g in the sensor's frame: CPose2D::inverseComposePoint's arithmetic, inline.
  const double ax = g.x() - b.sx, ay = g.y() - b.sy;
  const double bearing = std::atan2(-ax * b.sin + ay * b.cos, ax * b.cos + ay * b.sin);
  const double at = (e.dir * bearing - e.first) / e.step;
  const int size = b.size;
  if (!std::isfinite(at) || at < -1 || at > size) return false;
  const int reach = b.reach;
  const int mid = roundHalfAway(at);
  int best = -1;
  double best_d2 = gate * gate;
  for (int j = std::max(0, mid - reach); j <= std::min(size - 1, mid + reach); ++j) {
    // Selects instead of a branch: where along the window the nearest return lies follows no
    // pattern. A NaN distance (no return) is never <= best_d2.
    const double d2 = (b.nan_if_none[j] - g).squaredNorm();
    const bool nearer = d2 <= best_d2;
    best_d2 = nearer ? d2 : best_d2;
    best = nearer ? j : best;
  }
  if (best < 0) return false;
  // One surface: the neighbour no farther than three beam spacings at that range (a wall seen
  // at a slant) plus 10 cm.
  const double max_gap = 0.1 + 3 * std::abs(e.step) * e.range[best];
  double best_seg = -1;
  for (const int k : {best - 1, best + 1}) {
    if (k < 0 || k >= size || !e.valid[k]) continue;
    const Eigen::Vector2d t = e.point[k] - e.point[best];
    const double length = t.norm();
    if (length > max_gap || length < 1e-6) continue;
    // What normalized() gives: the same sum of squares (in the other order, which IEEE addition
    // does not mind), its root, and a division of each element by it.
    const Eigen::Vector2d nk(-t.y() / length, t.x() / length);
    const double d = std::abs(nk.dot(g - e.point[best]));
    if (best_seg < 0 || d < best_seg) best_seg = d, n = nk;
  }
  q = e.point[best];
  return best_seg >= 0;
}

/// Gauss-Newton on the later scan's points' distances to the earlier scan's segments.
mrpt::poses::CPose2D align(const Beams& beams, const ScanReturns& later,
                           const mrpt::poses::CPose2D& guess, int max_iterations) {
  mrpt::poses::CPose2D pose = guess;
  Eigen::Vector2d q, n;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity() * 1e-6;
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
    for (std::size_t i = 0; i < later.point.size(); ++i) {
      if (!later.valid[i]) continue;
      const Eigen::Vector2d& p = later.point[i];
      const double rx = c * p.x() - s * p.y(), ry = s * p.x() + c * p.y();
      const Eigen::Vector2d g(pose.x() + rx, pose.y() + ry);
      if (!pair(beams, g, pairingGate(later.range[i], it < kCoarseIterations), q, n)) continue;
      const double e = n.dot(g - q), k = inlierDistance(later.range[i]);
      const double w = 1.0 / (1.0 + (e * e) / (k * k));
      const Eigen::Vector3d j = poseJacobian(n, rx, ry);
      h += w * j * j.transpose();
      b += w * e * j;
    }
    const Eigen::Vector3d step = h.ldlt().solve(-b);
    if (!step.allFinite()) break;
    pose = {pose.x() + step.x(), pose.y() + step.y(), mrpt::math::wrapToPi(pose.phi() + step.z())};
    if (it >= kCoarseIterations && step.head<2>().norm() < 1e-4 && std::abs(step.z()) < 1e-5) {
      break;
    }
  }
  return pose;
}

}  // namespace

ScanReturns ScanReturns::of(const RangeData& rd) {
  ScanReturns out;
  out.sensor = rd.mount2D();
  out.first = rd.first, out.step = rd.step, out.dir = rd.dir;
  out.point.resize(rd.size());
  out.range.assign(rd.size(), 0.0);
  out.valid.assign(rd.size(), 0);
  for (std::size_t i = 0; i < rd.size(); ++i) {
    const double r = rd.ranges[i];
    const bool ret = rd.kinds[i] == BeamKind::Hit || rd.kinds[i] == BeamKind::Beyond;
    if (!ret || !(r > 0.0) || r >= rd.sensor_max_range) continue;
    const mrpt::math::TPoint2D p =
        out.sensor + mrpt::math::TPoint2D(r * rd.cos_angle[i], r * rd.sin_angle[i]);
    out.point[i] = {p.x, p.y};
    out.range[i] = r;
    out.valid[i] = 1;
    ++out.returns;
  }
  return out;
}

ScanToScanResult matchScans(const ScanReturns& earlier, const ScanReturns& later,
                            const mrpt::poses::CPose2D& guess, const ScanToScanLimits& limits) {
  ScanToScanResult r;
  r.increment = guess;
  if (earlier.step == 0 || later.returns < limits.min_inliers) {
    r.rejected = "too few returns";
    return r;
  }
  const Beams beams(earlier);  // once for the alignment and the inlier count
  const mrpt::poses::CPose2D matched = align(beams, later, guess, limits.max_iterations);
  if (!std::isfinite(matched.x()) || !std::isfinite(matched.y()) || !std::isfinite(matched.phi())) {
    r.rejected = "diverged";
    return r;
  }
  // Inliers at the matched pose, and what they pin down.
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  Eigen::Vector2d q, n;
  for (std::size_t i = 0; i < later.point.size(); ++i) {
    if (!later.valid[i]) continue;
    const Eigen::Vector2d g = [&] {
      const mrpt::math::TPoint2D t =
          matched + mrpt::math::TPoint2D(later.point[i].x(), later.point[i].y());
      return Eigen::Vector2d(t.x, t.y);
    }();
    if (!pair(beams, g, pairingGate(later.range[i], false), q, n)) continue;
    ++r.paired;
    if (std::abs(n.dot(g - q)) > inlierDistance(later.range[i])) continue;
    ++r.inliers;
    const Eigen::Vector3d j = poseJacobian(n, g.x() - matched.x(), g.y() - matched.y());
    info += j * j.transpose();
  }
  if (r.inliers < limits.min_inliers ||
      static_cast<double>(r.inliers) <
          limits.min_inlier_ratio * static_cast<double>(later.returns)) {
    r.rejected = "too few inliers";
    return r;
  }
  const mrpt::poses::CPose2D kept =
      keepConstrained(guess, matched, info / static_cast<double>(r.inliers), limits.min_constraint,
                      r.degenerate_directions);
  const double moved = std::hypot(kept.x() - guess.x(), kept.y() - guess.y());
  const double turned = std::abs(mrpt::math::wrapToPi(kept.phi() - guess.phi()));
  if (moved > limits.max_correction_m || turned > limits.max_correction_rad) {
    r.rejected = "correction too large";
    return r;
  }
  r.increment = kept;
  r.matched = true;
  return r;
}

}  // namespace dynamap
