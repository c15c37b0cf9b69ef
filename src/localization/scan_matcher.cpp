#include "dynamap/localization/scan_matcher.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>

#include <algorithm>
#include <climits>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "correlative_search.h"
#include "dynamap/base/angles.h"
#include "dynamap/base/ini.h"
#include "dynamap/base/option_table.h"
#include "dynamap/localization/icp_module.h"
#include "pose_constraint.h"

namespace dynamap {
namespace {

constexpr int kNormalRadius = 3;    // [cells] a wall's normal comes from a 7x7 neighbourhood
constexpr int kNormalMinCells = 4;  // ... of at least this many occupied cells
constexpr double kNormalMaxSpreadRatio = 0.2;  // ... spread across at most this along

/// The scan's hits in the robot's frame, short of the sensor's own maximum range (a reading
/// at it is no echo, whatever its flag says) and of the insertion range.
std::vector<mrpt::math::TPoint2D> scanPoints(const RangeData& rd) {
  std::vector<mrpt::math::TPoint2D> pts;
  const mrpt::poses::CPose2D sensor = rd.mount2D();
  pts.reserve(rd.size());
  for (std::size_t i = 0; i < rd.size(); ++i) {
    const double r = rd.ranges[i];
    if (rd.kinds[i] != BeamKind::Hit || r <= 0.0 || r >= rd.sensor_max_range) continue;
    pts.push_back(sensor + mrpt::math::TPoint2D(r * rd.cos_angle[i], r * rd.sin_angle[i]));
  }
  return pts;
}

/// What the occupied cells around one occupied cell say: where in the cell the wall runs (the
/// log-odds-weighted centroid of its 3x3 neighbourhood, in cells from its centre) and the wall's
/// unit normal (the minor axis of the occupied cells of its 7x7 neighbourhood; zero where the
/// cells do not line up: a lone cell or a blob pins nothing down).
struct CellWall {
  long wx = 0, wy = 0, w_sum = 1;  // the centroid is (wx, wy) / w_sum
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
};

template <typename Weight>
CellWall cellWall(int cx, int cy, int sx, int sy, const Weight& weight) {
  // Integer sums: exact, so the result is reproducible.
  long w_sum = 0, wx = 0, wy = 0, w5 = 0, sx5 = 0, sy5 = 0, sxx = 0, syy = 0, sxy = 0;
  for (int dy = -kNormalRadius; dy <= kNormalRadius; ++dy) {
    for (int dx = -kNormalRadius; dx <= kNormalRadius; ++dx) {
      const int nx = cx + dx, ny = cy + dy;
      if (nx < 0 || ny < 0 || nx >= sx || ny >= sy) continue;
      const long w = weight(nx, ny);
      if (w == 0) continue;
      if (std::abs(dx) <= 1 && std::abs(dy) <= 1) w_sum += w, wx += w * dx, wy += w * dy;
      // The wall's direction from the cells' layout alone: how occupied each cell is varies
      // along a wall and would tilt it.
      w5 += 1, sx5 += dx, sy5 += dy;
      sxx += dx * dx, syy += dy * dy, sxy += dx * dy;
    }
  }
  const double mx = double(sx5) / w5, my = double(sy5) / w5;
  Eigen::Matrix2d cov;
  cov << sxx / double(w5) - mx * mx, sxy / double(w5) - mx * my, sxy / double(w5) - mx * my,
      syy / double(w5) - my * my;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  CellWall c;
  c.wx = wx, c.wy = wy, c.w_sum = w_sum;
  if (w5 >= kNormalMinCells && eig.eigenvalues()(0) < kNormalMaxSpreadRatio * eig.eigenvalues()(1))
    c.normal = eig.eigenvectors().col(0);
  return c;
}

/// The weight of an S cell (by its raw value): how far below `occupied_threshold`'s log-odds its
/// own lie, 0 for a cell that is not occupied. getCell() is P(free): occupied above the threshold
/// <=> the raw cell below that value.
class OccupancyWeight {
 public:
  OccupancyWeight(const DynamicGridMap& map, double occupied_threshold)
      : raw_(map.getRawMap()),
        sx_(static_cast<int>(map.getSizeX())),
        occupied_below_(
            mrpt::maps::COccupancyGridMap2D::p2l(static_cast<float>(1.0 - occupied_threshold))) {}
  int operator()(int cx, int cy) const {
    const int v = raw_[static_cast<std::size_t>(cy) * sx_ + cx];
    return v < occupied_below_ ? occupied_below_ - v : 0;
  }

 private:
  const std::vector<DynamicGridMap::cellType>& raw_;
  int sx_, occupied_below_;
};

/// Where the wall through occupied cell (cx, cy) runs: the centroid of `cw`, in metres.
Eigen::Vector2d wallPoint(const DynamicGridMap& map, int cx, int cy, const CellWall& cw) {
  const double res = map.getResolution();
  return {map.idx2x(cx) + res * cw.wx / cw.w_sum, map.idx2y(cy) + res * cw.wy / cw.w_sum};
}

/// S's occupied cells in the box around the scan's end points seen from `guess`, each as the
/// centroid of the occupied cells of its 3x3 neighbourhood weighted by their log-odds. A wall
/// that lies on the border between two rows of cells fills both rows: their centres are half a
/// cell off the wall on either side, and point-to-point ICP would snap the scan onto one row.
/// The centroids of both rows lie on the wall itself.
/// `normals` receives, for each point, the unit normal of the wall through it: the minor axis
/// of the occupied cells of its 7x7 neighbourhood.
void mapPoints(const DynamicGridMap& map, const std::vector<mrpt::math::TPoint2D>& scan_pts,
               const mrpt::poses::CPose2D& guess, const ScanMatchOptions& o,
               mrpt::maps::CSimplePointsMap& out, std::vector<Eigen::Vector2d>& normals) {
  double x0 = guess.x(), x1 = guess.x(), y0 = guess.y(), y1 = guess.y();
  for (const auto& p : scan_pts) {
    const mrpt::math::TPoint2D g = guess + p;
    x0 = std::min(x0, g.x), x1 = std::max(x1, g.x);
    y0 = std::min(y0, g.y), y1 = std::max(y1, g.y);
  }
  const double m = o.window_margin_m;
  const int sx = static_cast<int>(map.getSizeX()), sy = static_cast<int>(map.getSizeY());
  const int cx0 = std::max(0, map.x2idx(x0 - m)), cy0 = std::max(0, map.y2idx(y0 - m));
  const int cx1 = std::min(sx - 1, map.x2idx(x1 + m)), cy1 = std::min(sy - 1, map.y2idx(y1 + m));
  const OccupancyWeight weight(map, o.occupied_threshold);
  for (int cy = cy0; cy <= cy1; ++cy) {
    for (int cx = cx0; cx <= cx1; ++cx) {
      if (weight(cx, cy) == 0) continue;
      const CellWall cw = cellWall(cx, cy, sx, sy, weight);
      const Eigen::Vector2d& n = cw.normal;
      const bool wall = n.squaredNorm() > 0;
      // On a wall, points every fifth of a cell along it: point-to-point ICP against one point
      // per cell would leave the scan free to slide by up to half a cell along each wall.
      const double res = map.getResolution();
      const Eigen::Vector2d q = wallPoint(map, cx, cy, cw);
      const double px = q.x(), py = q.y();
      for (int k = wall ? -2 : 0; k <= (wall ? 2 : 0); ++k) {
        const double along = 0.2 * k * res;  // tangent = (-n.y, n.x)
        out.insertPointFast(static_cast<float>(px - along * n.y()),
                            static_cast<float>(py + along * n.x()), 0);
        normals.push_back(n);
      }
    }
  }
  out.mark_as_modified();
}

}  // namespace

const OptionTable<ScanMatchOptions>& ScanMatchOptions::table() {
  using O = ScanMatchOptions;
  static const OptionTable<O> t(
      kSection,
      {
          {"occupied_threshold", &O::occupied_threshold, Range::open(0.5, 1), "",
           "S cells above this P(occ) are matched against"},
          {"window_margin_m", &O::window_margin_m, Range::closed(0, 5), "m",
           "MRPT's ICP: S is searched this far around the scan's end points"},
          {"min_map_points", &O::min_map_points, Range::closed(3, 100000), "",
           "fewer occupied S cells near the scan: odometry is used"},
          {"min_scan_points", &O::min_scan_points, Range::closed(3, 100000), "",
           "fewer scan points on what S holds: odometry is used"},
          {"overlap_distance_m", &O::overlap_distance_m, Range::openClosed(0, 2), "m",
           "scan points farther than this from S (seen from the guess) are not matched"},
          {"inlier_distance_m", &O::inlier_distance_m, Range::openClosed(0, 1), "m",
           "a matched scan point this close to S is an inlier"},
          {"min_inlier_ratio", &O::min_inlier_ratio, Range::closed(0, 1), "",
           "fewer inliers (fraction of scan points): odometry is used"},
          {"max_correction_m", &O::max_correction_m, Range::openClosed(0, 10), "m",
           "a larger correction of the odometry guess is rejected"},
          {"max_correction_deg", &O::max_correction_deg, Range::openClosed(0, 90), "deg",
           "a larger heading correction is rejected"},
          {"icp_threshold_dist_m", &O::icp_threshold_dist_m, Range::openClosed(0, 5), "m",
           "ICP's initial correspondence distance"},
          {"icp_smallest_threshold_dist_m", &O::icp_smallest_threshold_dist_m,
           Range::openClosed(0, 5), "m", "ICP stops when its halved distance falls below this"},
          {"icp_max_iterations", &O::icp_max_iterations, Range::closed(1, 1000), "",
           "ICP's iteration cap"},
          {"min_constraint", &O::min_constraint, Range::closed(0, 1), "",
           "pose directions the matched walls constrain less than this keep odometry's value"},
          {"search_xy_m", &O::search_xy_m, Range::closed(0, 2), "m",
           "grid search around the guess before ICP, in x and y (0: off)"},
          {"search_deg", &O::search_deg, Range::closed(0, 20), "deg", "...and in heading"},
          {"search_offset_cost", &O::search_offset_cost, Range::closed(0, 1000), "",
           "score (scan points) a search pose loses per cell^2 of offset"},
          {"point_to_line", &O::point_to_line, Range{}, "",
           "point-to-line ICP on S's cells (false: MRPT's point-to-point ICP)"},
          {"line_distance_m", &O::line_distance_m, Range::openClosed(0, 1), "m",
           "point-to-line ICP pairs a point with a wall this close"},
      });
  return t;
}

void ScanMatchOptions::load(const IniFile& ini) {
  table().load(ini, *this);
  validate(ini.name());
}

void ScanMatchOptions::validate(const std::string& src) const {
  table().checkRanges(*this, src);
  if (!(icp_smallest_threshold_dist_m <= icp_threshold_dist_m)) {
    rejectValue(src, kSection, "icp_smallest_threshold_dist_m",
                "must be in (0, icp_threshold_dist_m]");
  }
}

void ScanMatchOptions::writeIni(std::ostream& out) const {
  table().write(*this, out);
}

void ScanMatchOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                          const std::string& section) {
  load(IniFile::fromMrptSection(source, section, kSection));  // the same checks as an ini file
}

void ScanMatchOptions::dumpToTextStream(std::ostream& out) const {
  writeIni(out);
}

OccupiedByRawValue::OccupiedByRawValue(double threshold) {
  const long max = std::numeric_limits<Value>::max();
  table_.resize(static_cast<std::size_t>(max - kMin + 1));
  for (long v = kMin; v <= max; ++v) {
    table_[static_cast<std::size_t>(v - kMin)] =
        DynamicGridMap::staticOccupancyOfValue(static_cast<Value>(v)) > threshold;
  }
}

ScanMatcher::ScanMatcher(const ScanMatchOptions& options)
    : options_(options), occupied_(options.occupied_threshold) {
  options_.validate("scan matching options");
  requireIcpModule();  // a missing module stops the run before its first scan, not at it
}

namespace {

/// The points of `pts` that fall on what S already holds, seen from `start`, into `scan_map`. A
/// point in space S has never seen (a wall seen further along a corridor than ever before) has
/// no partner in S: the nearest one, the end of the known wall, would drag the robot back, or
/// turn it. Points farther from S's walls are also what S does not hold: people, objects that
/// moved (they are in D, never in S).
std::size_t overlapping(const mrpt::maps::CSimplePointsMap& reference,
                        const std::vector<mrpt::math::TPoint2D>& pts,
                        const mrpt::poses::CPose2D& start, double overlap_distance,
                        mrpt::maps::CSimplePointsMap& scan_map) {
  const float overlap_d2 = static_cast<float>(overlap_distance * overlap_distance);
  std::size_t n = 0;
  for (const auto& p : pts) {
    const mrpt::math::TPoint2D g = start + p;
    if (reference.kdTreeClosestPoint2DsqrError(static_cast<float>(g.x), static_cast<float>(g.y)) <=
        overlap_d2) {
      ++n;
      scan_map.insertPointFast(static_cast<float>(p.x), static_cast<float>(p.y), 0);
    }
  }
  scan_map.mark_as_modified();
  return n;
}

/// MRPT's classic point-to-point ICP of `scan_map` onto `reference`, from `start`.
mrpt::poses::CPose2D icpAlign(const mrpt::maps::CSimplePointsMap& reference,
                              const mrpt::maps::CSimplePointsMap& scan_map,
                              const mrpt::poses::CPose2D& start, const ScanMatchOptions& o,
                              ScanMatchResult& r) {
  IcpParams p;
  p.max_iterations = static_cast<unsigned>(o.icp_max_iterations);
  p.threshold_dist = o.icp_threshold_dist_m;
  p.threshold_ang = 0.15 * kDegToRad;
  p.alfa = 0.5;
  p.smallest_threshold_dist = o.icp_smallest_threshold_dist_m;
  unsigned iterations = 0;
  const mrpt::poses::CPose2D matched = icpAlignModule(reference, scan_map, start, p, iterations);
  r.icp_iterations = iterations;
  return matched;
}

/// The inliers at the matched pose (every scan point judged, not only those that overlapped S at
/// the guess) and their point-to-line information: a wall constrains the pose across itself
/// only, so in a straight corridor nothing fixes the position along it. `normal_near(g, n)`
/// says whether the point g (map frame) is an inlier, and sets n to its wall's unit normal.
template <typename NormalNear>
Eigen::Matrix3d inlierInformation(const std::vector<mrpt::math::TPoint2D>& pts,
                                  const mrpt::poses::CPose2D& matched, ScanMatchResult& r,
                                  const NormalNear& normal_near) {
  Eigen::Matrix3d fisher = Eigen::Matrix3d::Zero();
  Eigen::Vector2d n;
  r.inliers = 0;
  for (const auto& p : pts) {
    const mrpt::math::TPoint2D g = matched + p;
    if (!normal_near(g, n)) continue;
    ++r.inliers;
    const double rx = g.x - matched.x(), ry = g.y - matched.y();  // the point, rotated
    const Eigen::Vector3d j = poseJacobian(n, rx, ry);
    fisher += j * j.transpose();
  }
  r.inlier_ratio = static_cast<double>(r.inliers) / static_cast<double>(pts.size());
  return fisher;
}

/// ... for MRPT's ICP: an inlier is within inlier_distance of a reference point, whose wall's
/// normal is `normals`' entry.
Eigen::Matrix3d inlierInformation(const mrpt::maps::CSimplePointsMap& reference,
                                  const std::vector<Eigen::Vector2d>& normals,
                                  const std::vector<mrpt::math::TPoint2D>& pts,
                                  const mrpt::poses::CPose2D& matched, double inlier_distance,
                                  ScanMatchResult& r) {
  const float max_d2 = static_cast<float>(inlier_distance * inlier_distance);
  return inlierInformation(pts, matched, r, [&](const mrpt::math::TPoint2D& g, Eigen::Vector2d& n) {
    float qx, qy, d2;
    const std::size_t k = reference.kdTreeClosestPoint2D(static_cast<float>(g.x),
                                                         static_cast<float>(g.y), qx, qy, d2);
    if (d2 > max_d2) return false;
    n = normals[k];
    return true;
  });
}

/// keepConstrained() on a match's inliers, counting the directions kept at the guess in `r`.
mrpt::poses::CPose2D constrained(const mrpt::poses::CPose2D& guess,
                                 const mrpt::poses::CPose2D& matched, const Eigen::Matrix3d& info,
                                 ScanMatchResult& r, const ScanMatchOptions& o) {
  if (r.inliers == 0) return matched;
  return keepConstrained(guess, matched, info / static_cast<double>(r.inliers), o.min_constraint,
                         r.degenerate_directions);
}

/// The last judgement of a match: a correction too large to be drift, or too few inliers, keeps
/// the guess.
void accept(const mrpt::poses::CPose2D& guess, const mrpt::poses::CPose2D& matched,
            const mrpt::poses::CPose2D& corrected, const ScanMatchOptions& o, ScanMatchResult& r) {
  r.correction_m = std::hypot(corrected.x() - guess.x(), corrected.y() - guess.y());
  r.correction_rad = std::abs(mrpt::math::wrapToPi(corrected.phi() - guess.phi()));
  if (!std::isfinite(matched.x()) || !std::isfinite(matched.y()) || !std::isfinite(matched.phi()) ||
      r.correction_m > o.max_correction_m || r.correction_rad > o.max_correction_deg * kDegToRad) {
    r.fallback_reason = "correction too large";
  } else if (r.inlier_ratio < o.min_inlier_ratio) {
    r.fallback_reason = "low inlier ratio";
  } else {
    r.pose = corrected;
    r.matched = true;
  }
}

/// S's walls cell by cell, each worked out when first asked for: where in the cell the wall
/// runs and its normal (cellWall), as mapPoints places its reference points.
class WallCells {
 public:
  struct Wall {
    Eigen::Vector2d q, n;
  };

  WallCells(const DynamicGridMap& map, double occupied_threshold)
      : map_(map),
        weight_(map, occupied_threshold),
        sx_(static_cast<int>(map.getSizeX())),
        sy_(static_cast<int>(map.getSizeY())) {}

  /// The wall point q and unit normal n (zero where the cells do not line up) of the occupied
  /// cell within `reach` cells of (x, y) whose wall point is nearest to it, no farther than
  /// sqrt(max_d2); false if there is none.
  bool nearest(double x, double y, int reach, double max_d2, Eigen::Vector2d& q,
               Eigen::Vector2d& n) {
    const Wall* best = nullptr;
    double best_d2 = max_d2;
    forEachWall(map_.x2idx(x), map_.y2idx(y), reach, [&](const Wall& w) {
      const double d2 = (w.q - Eigen::Vector2d(x, y)).squaredNorm();
      if (d2 <= best_d2) best_d2 = d2, best = &w;
    });
    if (best == nullptr) return false;
    q = best->q, n = best->n;
    return true;
  }
  /// Appends the walls of the occupied cells within `reach` cells of cell (px, py) to `out`
  /// (pointers stay valid: the cache never moves an entry).
  void gather(int px, int py, int reach, std::vector<const Wall*>& out) {
    forEachWall(px, py, reach, [&](const Wall& w) { out.push_back(&w); });
  }
  /// Occupied cells asked for so far.
  std::size_t cells() const { return cache_.size(); }
  int cellX(double x) const { return map_.x2idx(x); }
  int cellY(double y) const { return map_.y2idx(y); }

 private:
  /// `f` of the wall of every occupied cell within `reach` cells of cell (px, py), row by row.
  template <typename F>
  void forEachWall(int px, int py, int reach, const F& f) {
    for (int cy = std::max(0, py - reach); cy <= std::min(sy_ - 1, py + reach); ++cy) {
      for (int cx = std::max(0, px - reach); cx <= std::min(sx_ - 1, px + reach); ++cx) {
        if (weight_(cx, cy) != 0) f(wall(cx, cy));
      }
    }
  }
  const Wall& wall(int cx, int cy) {
    const auto [it, added] = cache_.try_emplace(cx + cy * sx_);
    if (added) {
      const CellWall cw = cellWall(cx, cy, sx_, sy_, weight_);
      it->second = {wallPoint(map_, cx, cy, cw), cw.normal};
    }
    return it->second;
  }
  const DynamicGridMap& map_;
  OccupancyWeight weight_;
  int sx_, sy_;
  std::unordered_map<int, Wall> cache_;
};

/// Each point's candidate walls: the occupied cells around the cell it was gathered at, again
/// when the point has moved more than a cell from it.
struct Candidates {
  std::vector<const WallCells::Wall*> walls;
  std::vector<std::size_t> begin, end;
  std::vector<int> cx, cy;
};

/// Gauss-Newton on the points' distances to S's walls (point-to-line ICP; point-to-point where a
/// cell has no line), each point paired anew each iteration with the nearest wall within
/// `max_d` of it, residuals weighted by a Cauchy kernel.
mrpt::poses::CPose2D pointToLine(WallCells& walls, const std::vector<mrpt::math::TPoint2D>& pts,
                                 const mrpt::poses::CPose2D& start, double max_d, double res,
                                 int max_iterations, unsigned& iterations) {
  constexpr double kKernel = 0.03;  // [m] the Cauchy kernel's scale
  const int reach = static_cast<int>(std::ceil(max_d / res)) + 1;
  Candidates cand;
  cand.begin.assign(pts.size(), 0), cand.end.assign(pts.size(), 0);
  cand.cx.assign(pts.size(), INT_MIN / 2), cand.cy.assign(pts.size(), INT_MIN / 2);
  mrpt::poses::CPose2D pose = start;
  for (iterations = 0; iterations < static_cast<unsigned>(max_iterations);) {
    ++iterations;
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity() * 1e-6;
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double rx = c * pts[i].x - s * pts[i].y, ry = s * pts[i].x + c * pts[i].y;
      const Eigen::Vector2d g(pose.x() + rx, pose.y() + ry);
      const int px = walls.cellX(g.x()), py = walls.cellY(g.y());
      if (std::abs(px - cand.cx[i]) > 1 || std::abs(py - cand.cy[i]) > 1) {
        cand.cx[i] = px, cand.cy[i] = py, cand.begin[i] = cand.walls.size();
        walls.gather(px, py, reach, cand.walls);
        cand.end[i] = cand.walls.size();
      }
      const WallCells::Wall* best = nullptr;
      double best_d2 = max_d * max_d;
      for (std::size_t k = cand.begin[i]; k < cand.end[i]; ++k) {
        const double d2 = (cand.walls[k]->q - g).squaredNorm();
        if (d2 <= best_d2) best_d2 = d2, best = cand.walls[k];
      }
      if (best == nullptr) continue;
      auto add = [&](const Eigen::Vector2d& dir) {
        const double e = dir.dot(g - best->q), w = 1.0 / (1.0 + (e * e) / (kKernel * kKernel));
        const Eigen::Vector3d j = poseJacobian(dir, rx, ry);
        h += w * j * j.transpose();
        b += w * e * j;
      };
      if (best->n.squaredNorm() > 0) {
        add(best->n);
      } else {
        add({1, 0}), add({0, 1});
      }
    }
    const Eigen::Vector3d step = h.ldlt().solve(-b);
    if (!step.allFinite()) break;
    pose = {pose.x() + step.x(), pose.y() + step.y(), mrpt::math::wrapToPi(pose.phi() + step.z())};
    if (step.head<2>().norm() < 1e-4 && std::abs(step.z()) < 1e-4) break;
  }
  return pose;
}

/// inlierInformation on S's walls: a point is an inlier when a wall point lies within
/// inlier_distance_m of it, and that wall's normal says what it pins down.
Eigen::Matrix3d wallInformation(WallCells& walls, const std::vector<mrpt::math::TPoint2D>& pts,
                                const mrpt::poses::CPose2D& matched, const ScanMatchOptions& o,
                                double res, ScanMatchResult& r) {
  const int reach = static_cast<int>(std::ceil(o.inlier_distance_m / res));
  const double max_d2 = o.inlier_distance_m * o.inlier_distance_m;
  Eigen::Vector2d q;
  return inlierInformation(pts, matched, r, [&](const mrpt::math::TPoint2D& g, Eigen::Vector2d& n) {
    return walls.nearest(g.x, g.y, reach, max_d2, q, n);
  });
}

/// Steps 2 to 5 of a match with point-to-line ICP on S's cells instead of MRPT's ICP: no
/// reference point cloud and no KD-tree, each point's wall found in the cells around it.
void lineMatch(const DynamicGridMap& map, const std::vector<mrpt::math::TPoint2D>& pts,
               const mrpt::poses::CPose2D& guess, const mrpt::poses::CPose2D& start,
               const ScanMatchOptions& o, ScanMatchResult& r) {
  const double res = map.getResolution();
  WallCells walls(map, o.occupied_threshold);
  const int reach = static_cast<int>(std::ceil(o.overlap_distance_m / res));
  std::vector<mrpt::math::TPoint2D> on_s;
  Eigen::Vector2d q, n;
  for (const auto& p : pts) {
    const mrpt::math::TPoint2D g = start + p;
    if (walls.nearest(g.x, g.y, reach, o.overlap_distance_m * o.overlap_distance_m, q, n))
      on_s.push_back(p);
  }
  r.map_points = walls.cells();
  if (r.map_points < static_cast<std::size_t>(o.min_map_points)) {
    r.fallback_reason = "too few map points";
    return;
  }
  r.scan_points = on_s.size();
  if (r.scan_points < static_cast<std::size_t>(o.min_scan_points)) {
    r.fallback_reason = "too little overlap";
    return;
  }
  const mrpt::poses::CPose2D matched = pointToLine(walls, on_s, start, o.line_distance_m, res,
                                                   o.icp_max_iterations, r.icp_iterations);
  const Eigen::Matrix3d fisher = wallInformation(walls, pts, matched, o, res, r);
  accept(guess, matched, constrained(start, matched, fisher, r, o), o, r);
}

}  // namespace

ScanMatchResult ScanMatcher::match(const DynamicGridMap& map, const RangeData& rd,
                                   const mrpt::poses::CPose2D& guess) const {
  const ScanMatchOptions& o = options_;
  ScanMatchResult r;
  r.pose = guess;
  if (!rd.planar) {  // insertion skips it too: nothing to match in the floor's plane
    r.fallback_reason = "not horizontal";
    return r;
  }
  // 1. The scan's end points, in the robot's frame.
  const std::vector<mrpt::math::TPoint2D> pts = scanPoints(rd);
  r.scan_points = pts.size();
  if (pts.size() < static_cast<std::size_t>(o.min_scan_points)) {
    r.fallback_reason = "too few scan points";
    return r;
  }
  // 2. The occupied cells of S around where those points fall, seen from the guess moved to the
  //    best pose of a grid search: drift larger than the overlap gate is caught.
  const mrpt::poses::CPose2D start = correlativeGuess(map, pts, guess, o, occupied_);
  if (o.point_to_line) {
    lineMatch(map, pts, guess, start, o, r);
    return r;
  }
  mrpt::maps::CSimplePointsMap reference, scan_map;
  std::vector<Eigen::Vector2d> normals;
  mapPoints(map, pts, start, o, reference, normals);
  r.map_points = reference.size();
  if (r.map_points < static_cast<std::size_t>(o.min_map_points)) {
    r.fallback_reason = "too few map points";
    return r;
  }
  // 3. Only the points that fall on what S already holds.
  r.scan_points = overlapping(reference, pts, start, o.overlap_distance_m, scan_map);
  if (r.scan_points < static_cast<std::size_t>(o.min_scan_points)) {
    r.fallback_reason = "too little overlap";
    return r;
  }
  // 4. ICP, from the search's pose.
  const mrpt::poses::CPose2D matched = icpAlign(reference, scan_map, start, o, r);
  // 5. Inliers, and how well they pin each direction down: along a direction nothing fixes,
  //    ICP's answer is noise (or the pull of the map's edge), and the guess is kept.
  const Eigen::Matrix3d fisher =
      inlierInformation(reference, normals, pts, matched, o.inlier_distance_m, r);
  accept(guess, matched, constrained(start, matched, fisher, r, o), o, r);
  return r;
}

mrpt::poses::CPose2D keepConstrained(const mrpt::poses::CPose2D& guess,
                                     const mrpt::poses::CPose2D& matched,
                                     const Eigen::Matrix3d& info_per_point, double min_constraint,
                                     int& degenerate) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(info_per_point);
  const Eigen::Vector3d delta(matched.x() - guess.x(), matched.y() - guess.y(),
                              mrpt::math::wrapToPi(matched.phi() - guess.phi()));
  Eigen::Vector3d kept = Eigen::Vector3d::Zero();
  degenerate = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d v = eig.eigenvectors().col(i);
    if (eig.eigenvalues()(i) >= min_constraint) {
      kept += v.dot(delta) * v;
    } else {
      ++degenerate;
    }
  }
  return {guess.x() + kept.x(), guess.y() + kept.y(), mrpt::math::wrapToPi(guess.phi() + kept.z())};
}

}  // namespace dynamap
