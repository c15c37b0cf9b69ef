#include "dynamap/localization/consistency.h"

#include "dynamap/localization/likelihood_field.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace dynamap {
namespace {

struct IndexedPoint {
  double x, y;
  std::size_t scan;
};

/// The points of one cell, in scan order: those of every scan, or past kMaxCellPoints those of
/// every stride-th scan only (the stride doubling each time the cell fills again). A robot
/// standing still puts every scan's points in the same cells, and a query must not read them
/// all (a long log would take hours); whole scans are dropped, not single points, so the points
/// kept still show every place the scans saw in the cell.
struct Cell {
  static constexpr std::size_t kMaxCellPoints = 4096;
  static constexpr std::size_t kMaxStride = std::size_t(1) << 40;
  std::vector<IndexedPoint> points;
  std::size_t stride = 1;

  void add(const IndexedPoint& p) {
    if (p.scan % stride != 0) return;
    points.push_back(p);
    // One scan's own points (scan 0's always stay) may fill a cell past the bound: a scan has
    // no more points than beams, and the stride stops doubling well before it could overflow.
    while (points.size() > kMaxCellPoints && stride < kMaxStride) {
      stride *= 2;
      points.erase(std::remove_if(points.begin(), points.end(),
                                  [&](const IndexedPoint& q) { return q.scan % stride != 0; }),
                   points.end());
    }
  }
};

/// The stride through a scan of `n` points: point_stride, or more for a scan of more than
/// kMaxScanPoints used points (a laser of many thousand beams, or a file that says so), so that
/// no scan costs more than a bounded number of queries and partners.
constexpr std::size_t kMaxScanPoints = 2000;
std::size_t strideFor(std::size_t n, const ConsistencyOptions& o) {
  return std::max(o.point_stride, (n + kMaxScanPoints - 1) / kMaxScanPoints);
}

/// The squared distance from (x, y) to the nearest of `points` of a scan farther than `exclude`
/// in index from `scan` (infinity if none). Two minima side by side, then their minimum: one
/// chain of std::min made each point wait for the one before, and a minimum does not depend on
/// the order it is taken in (a point skipped counts as infinity, which never wins).
double cellNearest2(const std::vector<IndexedPoint>& points, double x, double y, std::size_t scan,
                    std::size_t exclude) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const auto d2 = [&](const IndexedPoint& q) {
    const std::size_t gap = q.scan > scan ? q.scan - scan : scan - q.scan;
    return gap <= exclude ? kNone : (q.x - x) * (q.x - x) + (q.y - y) * (q.y - y);
  };
  double b0 = kNone, b1 = kNone;
  std::size_t k = 0;
  for (; k + 1 < points.size(); k += 2)
    b0 = std::min(b0, d2(points[k])), b1 = std::min(b1, d2(points[k + 1]));
  if (k < points.size()) b0 = std::min(b0, d2(points[k]));
  return std::min(b0, b1);
}

/// The used points (every point_stride-th) of every scan, hashed by cells of cap_m: the nearest
/// point within cap_m of a query lies in the 3 x 3 cells around it.
class PointHash {
 public:
  PointHash(const std::vector<std::vector<MapPoint>>& scans, const ConsistencyOptions& o)
      : cell_(o.cap_m) {
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const std::size_t stride = strideFor(scans[i].size(), o);
      for (std::size_t k = 0; k < scans[i].size(); k += stride) {
        const MapPoint& p = scans[i][k];
        cells_[key(cellOf(p.x), cellOf(p.y))].add({p.x, p.y, i});
      }
    }
  }

  /// The squared distance from (x, y) to the nearest point of a scan farther than `exclude` in
  /// index from `scan`, at most `cap2`.
  double nearest2(double x, double y, std::size_t scan, std::size_t exclude, double cap2) const {
    double best = cap2;
    const std::int64_t cx = cellOf(x), cy = cellOf(y);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        const auto it = cells_.find(key(cx + dx, cy + dy));
        if (it == cells_.end()) continue;
        best = std::min(best, cellNearest2(it->second.points, x, y, scan, exclude));
      }
    }
    return best;
  }

 private:
  /// The cell of coordinate v; a coordinate too large for a cell index (or NaN) is put in the
  /// last cell (or cell 0) instead of overflowing the conversion.
  std::int64_t cellOf(double v) const {
    const double c = std::floor(v / cell_);
    if (!(c == c)) return 0;
    return static_cast<std::int64_t>(std::clamp(c, -kMaxCell, kMaxCell));
  }
  static constexpr double kMaxCell = 1e12;
  static std::uint64_t key(std::int64_t cx, std::int64_t cy) {
    return (static_cast<std::uint64_t>(cx) << 32) ^ static_cast<std::uint32_t>(cy);
  }
  double cell_;
  std::unordered_map<std::uint64_t, Cell> cells_;
};

/// The squared distance from p to the nearest of every stride-th point of `pts`, at most cap2.
/// Four minima side by side, then their minimum: one chain of std::min made each point wait for
/// the one before, and a minimum does not depend on the order it is taken in (a NaN distance is
/// skipped either way), so the result is the same.
double scanNearest2(const std::vector<MapPoint>& pts, std::size_t stride, const MapPoint& p,
                    double cap2) {
  const auto d2 = [&](std::size_t m) {
    const double dx = pts[m].x - p.x, dy = pts[m].y - p.y;
    return dx * dx + dy * dy;
  };
  double b0 = cap2, b1 = cap2, b2 = cap2, b3 = cap2;
  std::size_t m = 0;
  for (; m + 3 * stride < pts.size(); m += 4 * stride) {
    b0 = std::min(b0, d2(m)), b1 = std::min(b1, d2(m + stride));
    b2 = std::min(b2, d2(m + 2 * stride)), b3 = std::min(b3, d2(m + 3 * stride));
  }
  for (; m < pts.size(); m += stride) b0 = std::min(b0, d2(m));
  return std::min(std::min(b0, b1), std::min(b2, b3));
}

/// Mean capped distance from scan i's used points to scan i-1's, over every scan but the first.
void localFigure(const std::vector<std::vector<MapPoint>>& scans, const ConsistencyOptions& o,
                 Consistency& c) {
  const double cap2 = o.cap_m * o.cap_m;
  double sum = 0;
  for (std::size_t i = 1; i < scans.size(); ++i) {
    const auto& before = scans[i - 1];
    const std::size_t stride = strideFor(scans[i].size(), o);
    const std::size_t before_stride = strideFor(before.size(), o);
    for (std::size_t k = 0; k < scans[i].size(); k += stride) {
      const MapPoint& p = scans[i][k];
      sum += std::sqrt(scanNearest2(before, before_stride, p, cap2));
      ++c.local_points;
    }
  }
  c.local_m = c.local_points > 0 ? sum / static_cast<double>(c.local_points)
                                 : std::numeric_limits<double>::quiet_NaN();
}

void checkOptions(const ConsistencyOptions& o) {
  if (o.scan_stride == 0 || o.point_stride == 0 || !(o.cap_m > 0) || !std::isfinite(o.cap_m)) {
    throw std::invalid_argument("consistency: strides must be positive, cap_m positive and finite");
  }
}

}  // namespace

Consistency mapConsistency(const std::vector<std::vector<MapPoint>>& scans,
                           const ConsistencyOptions& o) {
  checkOptions(o);
  Consistency c;
  c.scans = scans.size();
  const PointHash hash(scans, o);
  const double cap2 = o.cap_m * o.cap_m;
  double sum = 0;
  for (std::size_t i = 0; i < scans.size(); i += o.scan_stride) {
    const std::size_t stride = strideFor(scans[i].size(), o);
    for (std::size_t k = 0; k < scans[i].size(); k += stride) {
      sum += std::sqrt(hash.nearest2(scans[i][k].x, scans[i][k].y, i, o.neighbour_scans, cap2));
      ++c.global_points;
    }
  }
  c.global_m = c.global_points > 0 ? sum / static_cast<double>(c.global_points)
                                   : std::numeric_limits<double>::quiet_NaN();
  localFigure(scans, o, c);
  return c;
}

ScanLayout::ScanLayout(const ConsistencyOptions& options, std::size_t max_points)
    : options_(options), max_points_(max_points) {
  checkOptions(options_);
}

bool ScanLayout::add(const std::vector<mrpt::math::TPoint2D>& hits) {
  const std::size_t stride = strideFor(hits.size(), options_);
  const std::size_t kept = (hits.size() + stride - 1) / stride;
  if (full_ || points_ + kept > max_points_) {
    full_ = true;
    return false;
  }
  std::vector<MapPoint>& pts = scans_.emplace_back();
  pts.reserve(kept);
  for (std::size_t k = 0; k < hits.size(); k += stride) pts.push_back({hits[k].x, hits[k].y});
  points_ += kept;
  return true;
}

bool ScanLayout::addScan(const mrpt::obs::CObservation2DRangeScan& scan,
                         const InsertionOptions& insertion) {
  if (full_) return false;
  insertion.rangeData(scan, rd_);
  return addRange(rd_);
}

bool ScanLayout::addRange(const RangeData& rd) {
  return !full_ && rd.planar && add(hitPoints(rd));  // full: not even the hits worked out
}

Consistency ScanLayout::score(const std::vector<mrpt::poses::CPose2D>& poses) const {
  if (poses.size() != scans_.size()) {
    throw std::invalid_argument("consistency: one pose per kept scan expected");
  }
  std::vector<std::vector<MapPoint>> laid(scans_.size());
  for (std::size_t i = 0; i < scans_.size(); ++i) {
    laid[i].reserve(scans_[i].size());
    for (const MapPoint& p : scans_[i]) {
      const mrpt::math::TPoint2D g = poses[i] + mrpt::math::TPoint2D(p.x, p.y);
      laid[i].push_back({g.x, g.y});
    }
  }
  ConsistencyOptions once = options_;  // the points kept are those the stride picks already
  once.point_stride = 1;
  return mapConsistency(laid, once);
}

}  // namespace dynamap
