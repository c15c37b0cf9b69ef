#include "dynamap/objects/object_tracker.h"

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {

// --- options -----------------------------------------------------------------------------------

namespace {

[[noreturn]] void reject(const std::string& source, const char* key, const std::string& why) {
  rejectValue(source, ObjectOptions::kSection, key, why);
}

void requireRange(const std::string& src, const char* key, double v, double lo, double hi,
                  const char* text) {
  requireInRange(src, ObjectOptions::kSection, key, v, lo, hi, text);
}

}  // namespace

void ObjectOptions::load(const IniFile& ini) {
  const std::string s = kSection;
  ini.requireKnownKeys(
      s, {"enabled", "join_distance", "min_cells", "min_size", "max_size", "confirm_scans",
          "settle_size", "wall_hug_distance", "thin_width", "thin_length", "size_tolerance",
          "reappear_distance", "follow_margin", "move_distance", "defer_s", "min_unseen_s",
          "match_time_scale", "match_distance_scale", "min_fit_cells"});
  enabled = ini.getBool(s, "enabled", enabled);
  join_distance = ini.getDouble(s, "join_distance", join_distance);
  min_cells = static_cast<int>(ini.getInt(s, "min_cells", min_cells));
  min_size = ini.getDouble(s, "min_size", min_size);
  max_size = ini.getDouble(s, "max_size", max_size);
  confirm_scans = static_cast<int>(ini.getInt(s, "confirm_scans", confirm_scans));
  settle_size = ini.getDouble(s, "settle_size", settle_size);
  wall_hug_distance = ini.getDouble(s, "wall_hug_distance", wall_hug_distance);
  thin_width = ini.getDouble(s, "thin_width", thin_width);
  thin_length = ini.getDouble(s, "thin_length", thin_length);
  size_tolerance = ini.getDouble(s, "size_tolerance", size_tolerance);
  reappear_distance = ini.getDouble(s, "reappear_distance", reappear_distance);
  follow_margin = ini.getDouble(s, "follow_margin", follow_margin);
  move_distance = ini.getDouble(s, "move_distance", move_distance);
  defer_s = ini.getDouble(s, "defer_s", defer_s);
  min_unseen_s = ini.getDouble(s, "min_unseen_s", min_unseen_s);
  match_time_scale = ini.getDouble(s, "match_time_scale", match_time_scale);
  match_distance_scale = ini.getDouble(s, "match_distance_scale", match_distance_scale);
  min_fit_cells = static_cast<int>(ini.getInt(s, "min_fit_cells", min_fit_cells));
  validate(ini.name());
}

void ObjectOptions::validate(const std::string& src) const {
  requireRange(src, "join_distance", join_distance, 0.01, 2.0, "in [0.01, 2] m");
  requireRange(src, "min_cells", min_cells, 1, 1000, "in [1, 1000]");
  requireRange(src, "max_size", max_size, 0.0, 20.0, "in (0, 20] m");
  if (!(max_size > 0.0)) reject(src, "max_size", "must be > 0 m");
  requireRange(src, "min_size", min_size, 0.0, 20.0, "in [0, max_size) m");
  if (!(min_size < max_size)) reject(src, "min_size", "must be below max_size");
  requireRange(src, "confirm_scans", confirm_scans, 1, 1000, "in [1, 1000]");
  requireRange(src, "settle_size", settle_size, 0.0, 1.0, "in [0, 1] m");
  requireRange(src, "wall_hug_distance", wall_hug_distance, 0.0, 1.0, "in [0, 1] m");
  requireRange(src, "thin_width", thin_width, 0.0, 1.0, "in [0, 1] m");
  requireRange(src, "thin_length", thin_length, 0.0, 20.0, "in [0, 20] m");
  requireRange(src, "size_tolerance", size_tolerance, 1e-9, 5.0, "in (0, 5] m");
  requireRange(src, "reappear_distance", reappear_distance, 1e-9, 10.0, "in (0, 10] m");
  requireRange(src, "follow_margin", follow_margin, 0.0, 5.0, "in [0, 5] m");
  requireRange(src, "move_distance", move_distance, 1e-9, 10.0, "in (0, 10] m");
  requireRange(src, "defer_s", defer_s, 0.0, 1e6, "in [0, 1e6] s");
  requireRange(src, "min_unseen_s", min_unseen_s, 0.0, 1e6, "in [0, 1e6] s");
  requireRange(src, "match_time_scale", match_time_scale, 1e-9, 1e9, "> 0 s");
  requireRange(src, "match_distance_scale", match_distance_scale, 1e-9, 1e9, "> 0 m");
  requireRange(src, "min_fit_cells", min_fit_cells, 3, 1000, "in [3, 1000]");
}

void ObjectOptions::writeIni(std::ostream& out) const {
  out << std::setprecision(10);
  out << "[" << kSection << "]\n"
      << "enabled = " << (enabled ? "true" : "false") << " ; track objects at all\n"
      << "join_distance = " << join_distance << " ; [m] object cells this close form one cluster\n"
      << "min_cells = " << min_cells << " ; fewer cells is not an object\n"
      << "min_size = " << min_size << " ; [m] smaller estimated sizes are noise\n"
      << "max_size = " << max_size << " ; [m] larger clusters are not objects\n"
      << "confirm_scans = " << confirm_scans << " ; scans a new cluster must last to be reported\n"
      << "settle_size = " << settle_size
      << " ; [m] ...with its size changing no more than this from scan to scan\n"
      << "wall_hug_distance = " << wall_hug_distance
      << " ; [m] D cells this close to S-occupied cells are wall noise\n"
      << "thin_width = " << thin_width
      << " ; [m] a cluster this thin (std across its axis) near a wall is wall noise...\n"
      << "thin_length = " << thin_length << " ; [m] ...when at least this long\n"
      << "size_tolerance = " << size_tolerance << " ; [m] identity by size: max size difference\n"
      << "reappear_distance = " << reappear_distance
      << " ; [m] back this close to its last place: reappeared\n"
      << "follow_margin = " << follow_margin
      << " ; [m] new cells within an object's radius + this continue it\n"
      << "move_distance = " << move_distance << " ; [m] drift that counts as a move\n"
      << "defer_s = " << defer_s
      << " ; [s] max wait for an out-of-sight place to tell a move from a new object\n"
      << "min_unseen_s = " << min_unseen_s
      << " ; [s] an object seen in place more recently did not move unseen\n"
      << "match_time_scale = " << match_time_scale
      << " ; [s] identity: cost of time since vanishing\n"
      << "match_distance_scale = " << match_distance_scale
      << " ; [m] identity: cost of distance from the last place\n"
      << "min_fit_cells = " << min_fit_cells << " ; cells needed for a circle fit\n";
}

// --- pure steps ----------------------------------------------------------------------------------

bool fitCircle(const std::vector<double>& xs, const std::vector<double>& ys, Circle& out) {
  const std::size_t n = std::min(xs.size(), ys.size());
  if (n < 3) return false;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) mx += xs[i], my += ys[i];
  mx /= n;
  my /= n;
  // Kasa: x^2 + y^2 + D x + E y + F = 0 in least squares, in centred coordinates.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const double x = xs[i] - mx, y = ys[i] - my;
    const Eigen::Vector3d row(x, y, 1.0);
    ata += row * row.transpose();
    atb += row * (-(x * x + y * y));
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(ata);
  if (lu.rank() < 3) return false;
  const Eigen::Vector3d def = lu.solve(atb);
  double a = -def(0) / 2, b = -def(1) / 2;
  const double r2 = a * a + b * b - def(2);
  if (!(r2 > 0)) return false;
  double r = std::sqrt(r2);
  // Gauss-Newton on the geometric distances: Kasa shrinks circles fitted to short arcs.
  for (int it = 0; it < 10; ++it) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = xs[i] - mx - a, dy = ys[i] - my - b;
      const double d = std::max(1e-12, std::sqrt(dx * dx + dy * dy));
      const Eigen::Vector3d j(-dx / d, -dy / d, -1.0);
      jtj += j * j.transpose();
      jtr += j * (d - r);
    }
    const Eigen::FullPivLU<Eigen::Matrix3d> lu2(jtj);
    if (lu2.rank() < 3) break;
    const Eigen::Vector3d step = lu2.solve(-jtr);
    a += step(0);
    b += step(1);
    r += step(2);
    if (step.norm() < 1e-7) break;
  }
  if (!(r > 0) || !std::isfinite(r) || !std::isfinite(a) || !std::isfinite(b)) return false;
  out = {a + mx, b + my, r};
  return true;
}

namespace {

// The standard deviation of points across their main direction: ~0 for a straight row.
double minorAxisStd(const std::vector<double>& xs, const std::vector<double>& ys) {
  const double n = static_cast<double>(xs.size());
  if (xs.size() < 2) return 0;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) mx += xs[i], my += ys[i];
  mx /= n;
  my /= n;
  double sxx = 0, syy = 0, sxy = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    sxx += (xs[i] - mx) * (xs[i] - mx);
    syy += (ys[i] - my) * (ys[i] - my);
    sxy += (xs[i] - mx) * (ys[i] - my);
  }
  sxx /= n;
  syy /= n;
  sxy /= n;
  const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
  const double minor = 0.5 * tr - std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  return std::sqrt(std::max(0.0, minor));
}

// Moves `c` (from a free fit) to the centre that best puts the points at distance r from it.
/// Indices of the convex hull's corners of the first n points (Andrew's monotone chain), in
/// order; all points when fewer than 3.
std::vector<std::size_t> convexHull(const std::vector<double>& xs, const std::vector<double>& ys,
                                    std::size_t n) {
  std::vector<std::size_t> idx(n);
  for (std::size_t i = 0; i < n; ++i) idx[i] = i;
  if (n < 3) return idx;
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
    return xs[a] < xs[b] || (xs[a] == xs[b] && ys[a] < ys[b]);
  });
  auto cross = [&](std::size_t o, std::size_t a, std::size_t b) {
    return (xs[a] - xs[o]) * (ys[b] - ys[o]) - (ys[a] - ys[o]) * (xs[b] - xs[o]);
  };
  std::vector<std::size_t> hull(2 * n);
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], idx[i]) <= 0) --k;
    hull[k++] = idx[i];
  }
  for (std::size_t i = n - 1, t = k + 1; i-- > 0;) {  // upper chain
    while (k >= t && cross(hull[k - 2], hull[k - 1], idx[i]) <= 0) --k;
    hull[k++] = idx[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

void fitCentre(const std::vector<double>& xs, const std::vector<double>& ys, double r, Circle& c) {
  double a = c.cx, b = c.cy;
  for (int it = 0; it < 15; ++it) {
    Eigen::Matrix2d jtj = Eigen::Matrix2d::Zero();
    Eigen::Vector2d jtr = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double dx = xs[i] - a, dy = ys[i] - b;
      const double d = std::max(1e-12, std::sqrt(dx * dx + dy * dy));
      const Eigen::Vector2d j(-dx / d, -dy / d);
      jtj += j * j.transpose();
      jtr += j * (d - r);
    }
    if (std::abs(jtj.determinant()) < 1e-12) break;
    const Eigen::Vector2d step = jtj.ldlt().solve(-jtr);
    a += step(0);
    b += step(1);
    if (step.norm() < 1e-7) break;
  }
  if (std::isfinite(a) && std::isfinite(b)) c = {a, b, r};
}

}  // namespace

ShapeEstimate estimateShape(const std::vector<CellXY>& cells, double res,
                            const ObjectOptions& options) {
  ShapeEstimate s;
  s.cells = cells.size();
  if (cells.empty()) return s;
  std::vector<double> xs, ys;
  xs.reserve(cells.size());
  ys.reserve(cells.size());
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const CellXY& c : cells) {
    xs.push_back((c.x + 0.5) * res);
    ys.push_back((c.y + 0.5) * res);
    x0 = std::min(x0, xs.back());
    x1 = std::max(x1, xs.back());
    y0 = std::min(y0, ys.back());
    y1 = std::max(y1, ys.back());
  }
  // The widest extent: a convex object's visible outline is as wide as the object. It joins
  // two corners of the cells' convex hull.
  double width2 = 0;
  const std::vector<std::size_t> hull = convexHull(xs, ys, xs.size());
  for (std::size_t i = 0; i < hull.size(); ++i) {
    for (std::size_t j = i + 1; j < hull.size(); ++j) {
      const double dx = xs[hull[i]] - xs[hull[j]], dy = ys[hull[i]] - ys[hull[j]];
      width2 = std::max(width2, dx * dx + dy * dy);
    }
  }
  const double width = std::sqrt(width2);
  s.thickness = minorAxisStd(xs, ys);
  s.length = width;
  Circle c{};
  // (No circle for what is wider than any object: a wall.)
  if (static_cast<int>(cells.size()) >= options.min_fit_cells && width <= options.max_size &&
      fitCircle(xs, ys, c)) {
    double d = 2 * c.r;
    // Sane: as wide as the cells at least (less a cell of quantisation), not much wider than
    // them (a short arc of a huge circle is a wall, not a cylinder), within max_size.
    if (d >= width - res && d <= 1.6 * (width + res) && d <= options.max_size) {
      // An arc of grid cells looks flatter than the surface: the fit overshoots, while a
      // convex object's outline is exactly as wide as the object. Keep the smaller, and centre
      // the circle of that size on the cells.
      if (d > width + res) {
        d = width + res;
        fitCentre(xs, ys, 0.5 * d, c);
      }
      s.circle = true;
      s.cx = c.cx;
      s.cy = c.cy;
      s.size = d;
      s.x_min = c.cx - 0.5 * d;
      s.x_max = c.cx + 0.5 * d;
      s.y_min = c.cy - 0.5 * d;
      s.y_max = c.cy + 0.5 * d;
      return s;
    }
  }
  s.size = width + res;
  s.cx = 0.5 * (x0 + x1);
  s.cy = 0.5 * (y0 + y1);
  s.x_min = x0 - 0.5 * res;
  s.x_max = x1 + 0.5 * res;
  s.y_min = y0 - 0.5 * res;
  s.y_max = y1 + 0.5 * res;
  return s;
}

namespace {

// Offsets of the cells within `join_cells` (Euclidean, centre to centre) of a cell.
std::vector<CellXY> joinOffsets(double join_cells) {
  std::vector<CellXY> off;
  const int r = static_cast<int>(std::floor(join_cells + 1e-9));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if ((dx || dy) && dx * dx + dy * dy <= join_cells * join_cells + 1e-9)
        off.push_back({dx, dy});
    }
  }
  return off;
}

// Breadth-first growth of one cluster from `seed` over the cells `usable` accepts.
template <typename Usable>
std::vector<CellXY> growCluster(CellKey seed, const std::vector<CellXY>& offsets, Usable usable,
                                std::unordered_set<CellKey>& visited) {
  std::vector<CellXY> out;
  std::vector<CellKey> queue{seed};
  visited.insert(seed);
  while (!queue.empty()) {
    const CellKey k = queue.back();
    queue.pop_back();
    const CellXY c = cellOf(k);
    out.push_back(c);
    for (const CellXY& o : offsets) {
      const CellKey n = cellKey(c.x + o.x, c.y + o.y);
      if (visited.count(n) || !usable(n)) continue;
      visited.insert(n);
      queue.push_back(n);
    }
  }
  // Deterministic content order, whatever the hash set's order.
  std::sort(out.begin(), out.end(),
            [](CellXY a, CellXY b) { return cellKey(a.x, a.y) < cellKey(b.x, b.y); });
  return out;
}

double wrapAngle(double a) {
  while (a > M_PI) a -= 2 * M_PI;
  while (a <= -M_PI) a += 2 * M_PI;
  return a;
}

}  // namespace

bool estimatePointShape(const std::vector<double>& xs, const std::vector<double>& ys, double gap,
                        double sensor_x, double sensor_y, const ObjectOptions& options,
                        ShapeEstimate& out) {
  const std::size_t n = std::min(xs.size(), ys.size());
  if (n == 0 || static_cast<int>(n) < options.min_fit_cells) return false;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300, mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    x0 = std::min(x0, xs[i]);
    x1 = std::max(x1, xs[i]);
    y0 = std::min(y0, ys[i]);
    y1 = std::max(y1, ys[i]);
    mx += xs[i];
    my += ys[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  // The widest chord (the visible outline of a convex object) joins two corners of the points'
  // convex hull: O(n log n) for the hull, then pairs of its few corners.
  const std::vector<std::size_t> hull = convexHull(xs, ys, n);
  double width2 = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    for (std::size_t j = i + 1; j < hull.size(); ++j) {
      const double dx = xs[hull[i]] - xs[hull[j]], dy = ys[hull[i]] - ys[hull[j]];
      width2 = std::max(width2, dx * dx + dy * dy);
    }
  }
  const double width = std::sqrt(width2);
  ShapeEstimate s;
  s.cells = n;
  s.length = width;
  s.thickness = minorAxisStd(xs, ys);
  Circle c{};
  if (fitCircle(xs, ys, c)) {
    const double d = 2 * c.r;
    double rss = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double ex = xs[i] - c.cx, ey = ys[i] - c.cy;
      const double e = std::sqrt(ex * ex + ey * ey) - c.r;
      rss += e * e;
    }
    const double rms = std::sqrt(rss / static_cast<double>(n));
    // Sane: the points span a few centimetres of arc at least, lie on it (range noise of a
    // centimetre or two), it is no narrower than
    // they are and not far wider (a short flat arc fits any large circle), and it bulges
    // towards the sensor, as a solid seen from outside does.
    const bool beyond =
        std::hypot(c.cx - sensor_x, c.cy - sensor_y) > std::hypot(mx - sensor_x, my - sensor_y);
    if (width >= 0.04 && rms <= 0.02 && d >= width - 0.02 &&
        d <= std::max(1.5 * width, width + 0.06) && d <= options.max_size && beyond) {
      s.circle = true;
      s.cx = c.cx;
      s.cy = c.cy;
      s.size = std::max(d, width);
      s.x_min = c.cx - 0.5 * s.size;
      s.x_max = c.cx + 0.5 * s.size;
      s.y_min = c.cy - 0.5 * s.size;
      s.y_max = c.cy + 0.5 * s.size;
      out = s;
      return true;
    }
  }
  s.size = width + gap;
  s.cx = 0.5 * (x0 + x1);
  s.cy = 0.5 * (y0 + y1);
  s.x_min = std::min(x0, s.cx - 0.5 * s.size);
  s.x_max = std::max(x1, s.cx + 0.5 * s.size);
  s.y_min = std::min(y0, s.cy - 0.5 * s.size);
  s.y_max = std::max(y1, s.cy + 0.5 * s.size);
  out = s;
  return true;
}

std::vector<std::vector<CellXY>> clusterCells(const std::vector<CellXY>& cells, double join_cells) {
  std::unordered_set<CellKey> all;
  std::vector<CellKey> keys;
  for (const CellXY& c : cells) {
    if (all.insert(cellKey(c.x, c.y)).second) keys.push_back(cellKey(c.x, c.y));
  }
  std::sort(keys.begin(), keys.end());
  const auto offsets = joinOffsets(join_cells);
  std::unordered_set<CellKey> visited;
  std::vector<std::vector<CellXY>> clusters;
  for (const CellKey k : keys) {
    if (visited.count(k)) continue;
    clusters.push_back(growCluster(
        k, offsets, [&](CellKey n) { return all.count(n) > 0; }, visited));
  }
  return clusters;
}

ScanView makeScanView(const mrpt::obs::CObservation2DRangeScan& scan,
                      const mrpt::poses::CPose2D& robot, double max_range) {
  ScanView v;
  const std::size_t n = scan.getScanSize();
  if (n == 0) return v;
  const mrpt::poses::CPose3D sensor3d = mrpt::poses::CPose3D(robot) + scan.sensorPose;
  const mrpt::poses::CPose2D sensor(sensor3d);
  const bool upside_down =
      sensor3d.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>()(2, 2) < 0;
  v.x = sensor.x();
  v.y = sensor.y();
  v.phi = sensor.phi();
  v.first = n > 1 ? -0.5 * scan.aperture : 0.0;
  v.step = n > 1 ? scan.aperture / static_cast<double>(n - 1) : 0.0;
  v.dir = (scan.rightToLeft ^ upside_down) ? 1.0 : -1.0;
  v.max_range = max_range;
  v.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = scan.getScanRange(i);
    const bool ok = scan.getScanRangeValidity(i) && std::isfinite(r) && r >= 0.0f;
    v.ranges[i] = ok ? std::min(r, static_cast<float>(max_range)) : -1.0f;
  }
  return v;
}

PlaceView viewOf(const ScanView& v, double cx, double cy, double r, double margin) {
  if (v.empty()) return PlaceView::NotInView;
  const double dx = cx - v.x, dy = cy - v.y;
  const double d = std::hypot(dx, dy);
  if (d <= r || d - r > v.max_range) return PlaceView::NotInView;
  const double bearing = std::atan2(dy, dx);
  const double u = v.dir * wrapAngle(bearing - v.phi);
  const double half = std::asin(std::min(1.0, r / d));
  const long n = static_cast<long>(v.ranges.size());
  long lo = 0, hi = 0;
  if (n > 1) {
    lo = std::max(0L, static_cast<long>(std::ceil((u - half - v.first) / v.step)));
    hi = std::min(n - 1, static_cast<long>(std::floor((u + half - v.first) / v.step)));
  } else if (std::abs(u - v.first) > half) {
    return PlaceView::NotInView;
  }
  int seen_free = 0, seen_occupied = 0;
  for (long i = lo; i <= hi; ++i) {
    const double range = v.ranges[static_cast<std::size_t>(i)];
    if (range < 0) continue;
    const double off = wrapAngle(v.phi + v.dir * (v.first + v.step * i) - bearing);
    const double along = d * std::cos(off), perp = d * std::abs(std::sin(off));
    if (perp > r) continue;
    const double entry = along - std::sqrt(r * r - perp * perp);
    if (range < entry - margin) continue;  // hidden behind something nearer
    if (range <= entry + margin) {
      ++seen_occupied;
    } else {
      ++seen_free;  // the beam went past where the object's surface would be
    }
  }
  if (seen_occupied > 0 && seen_occupied >= seen_free) return PlaceView::SeenOccupied;
  if (seen_free > 0) return PlaceView::SeenFree;
  return PlaceView::NotInView;
}

int chooseIdentity(const ShapeEstimate& det, double t,
                   const std::vector<IdentityCandidate>& candidates, const ObjectOptions& o) {
  // Present objects not seen at their place are a weaker explanation than absent ones: they
  // pay half a size tolerance.
  constexpr double kUnseenPenalty = 0.5;
  int best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const IdentityCandidate& c = candidates[i];
    const double ds = std::abs(c.size - det.size);
    if (ds > o.size_tolerance) continue;
    if (!c.absent && c.view == PlaceView::SeenOccupied) continue;
    const double age = c.absent ? std::max(0.0, t - c.vanished_t) : 0.0;
    const double dist = std::hypot(c.cx - det.cx, c.cy - det.cy);
    const double cost = ds / o.size_tolerance + age / o.match_time_scale +
                        dist / o.match_distance_scale + (c.absent ? 0.0 : kUnseenPenalty);
    if (cost < best_cost) {
      best_cost = cost;
      best = static_cast<int>(i);
    }
  }
  return best;
}

const char* toString(ObjectState s) {
  return s == ObjectState::Present ? "present" : "absent";
}

const char* toString(ObjectEvent e) {
  switch (e) {
    case ObjectEvent::New:
      return "new";
    case ObjectEvent::Moved:
      return "moved";
    case ObjectEvent::Disappeared:
      return "disappeared";
    case ObjectEvent::Reappeared:
      return "reappeared";
  }
  return "?";
}

// --- the tracker -------------------------------------------------------------------------------

ObjectTracker::ObjectTracker(const ObjectOptions& options) : options_(options) {
  options_.validate("ObjectTracker options");
}

void ObjectTracker::update(const DynamicGridMap& map, const ScanView& view, double t,
                           std::size_t scan_index) {
  events_before_update_ = events_.size();
  touched_.clear();
  if (!options_.enabled) return;
  std::vector<CellKey> dirty;
  // 1. Fold this scan's threshold crossings into the set of object cells.
  foldChanges(map, dirty);
  // 2. Re-cluster around them only; clusters go to the track owning most of their cells.
  if (!dirty.empty()) recluster(map, dirty);
  // 2b. This scan's hit points on them, for a finer size.
  if (!view.empty()) sensor_x_ = view.x, sensor_y_ = view.y;
  collectPoints(map, view);
  // 3. Objects whose cells all faded were seen gone: disappeared.
  dropLostTracks(t, scan_index);
  // 4. Places left by unseen moves: seen free ends them, seen occupied revives them.
  checkStalePlaces(view, t, scan_index);
  // 5. Clusters that lasted confirm_scans get an identity by size: new, moved, reappeared.
  confirmTentatives(view, t, scan_index);
  // 6. Present objects that drifted (a person walking) moved; refresh the table.
  checkDrift(t, scan_index);
  updateLastSeen(view, t);
}

void ObjectTracker::foldChanges(const DynamicGridMap& map, std::vector<CellKey>& dirty) {
  resolution_ = map.getResolution();
  origin_x_ = static_cast<int>(std::lround(map.getXMin() / resolution_));
  origin_y_ = static_cast<int>(std::lround(map.getYMin() / resolution_));
  const std::size_t sx = map.getSizeX();
  for (const std::uint32_t idx : map.changedObjectCells()) {
    const int cx = static_cast<int>(idx % sx), cy = static_cast<int>(idx / sx);
    const CellKey k = cellKey(cx + origin_x_, cy + origin_y_);
    if (map.isObjectIndex(idx)) {
      cells_.insert(k);
    } else {
      cells_.erase(k);
    }
    dirty.push_back(k);
  }
}

bool ObjectTracker::isWallNoise(const DynamicGridMap& map, CellXY c) const {
  return options_.wall_hug_distance > 0 && nearNotFree(map, c, options_.wall_hug_distance);
}

bool ObjectTracker::nearNotFree(const DynamicGridMap& map, CellXY c, double distance) const {
  const double rc = distance / resolution_;
  const int r = static_cast<int>(std::floor(rc + 1e-9));
  const double r2 = rc * rc;
  const int gx = c.x - origin_x_, gy = c.y - origin_y_;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > r2 + 1e-9) continue;
      if (!map.isStaticFree(gx + dx, gy + dy)) return true;
    }
  }
  return false;
}

int ObjectTracker::ownerOfMost(const std::vector<CellXY>& cluster) const {
  std::map<int, std::size_t> votes;
  for (const CellXY& c : cluster) {
    const auto it = owner_.find(cellKey(c.x, c.y));
    if (it != owner_.end()) ++votes[it->second];
  }
  int best = 0;
  std::size_t most = 0;
  for (const auto& kv : votes) {
    if (kv.second > most) best = kv.first, most = kv.second;
  }
  return best;
}

int ObjectTracker::followedTrack(const ShapeEstimate& s) const {
  int best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& kv : tracks_) {
    const Track& tr = kv.second;
    if (tr.stale_of || tr.cells.empty()) continue;
    const double d = std::hypot(tr.shape.cx - s.cx, tr.shape.cy - s.cy);
    if (d <= 0.5 * tr.shape.size + options_.follow_margin && d < best_d) {
      best_d = d;
      best = kv.first;
    }
  }
  return best;
}

void ObjectTracker::recluster(const DynamicGridMap& map, const std::vector<CellKey>& dirty) {
  const double join_cells = options_.join_distance / resolution_;
  const auto offsets = joinOffsets(join_cells);
  std::unordered_map<CellKey, bool> noise;  // wall-noise memo for this scan
  auto usable = [&](CellKey k) {
    if (!cells_.count(k)) return false;
    auto it = noise.find(k);
    if (it == noise.end()) it = noise.emplace(k, isWallNoise(map, cellOf(k))).first;
    return !it->second;
  };
  // Tracks that lose cells: owners of faded cells.
  std::set<int> touched;
  for (const CellKey k : dirty) {
    const auto it = owner_.find(k);
    if (it != owner_.end() && !cells_.count(k)) {
      touched.insert(it->second);
      owner_.erase(it);
    }
  }
  // Every cluster within reach of a changed cell (a removed cell may have split its cluster:
  // each part still has a cell within the join distance of it).
  std::unordered_set<CellKey> visited;
  std::vector<std::vector<CellXY>> clusters;
  for (const CellKey k : dirty) {
    const CellXY c = cellOf(k);
    for (std::size_t i = 0; i <= offsets.size(); ++i) {
      const CellKey n = i == offsets.size() ? k : cellKey(c.x + offsets[i].x, c.y + offsets[i].y);
      if (visited.count(n) || !usable(n)) continue;
      clusters.push_back(growCluster(n, offsets, usable, visited));
    }
  }
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) {
    return cellKey(a[0].x, a[0].y) < cellKey(b[0].x, b[0].y);
  });
  // Each cluster to the track owning most of its cells, or to a track it continues, or new.
  std::map<int, std::vector<CellKey>> gained;
  for (const auto& cl : clusters) {
    for (const CellXY& c : cl) {
      const auto it = owner_.find(cellKey(c.x, c.y));
      if (it != owner_.end()) touched.insert(it->second);
    }
    int key = ownerOfMost(cl);
    if (!key) key = followedTrack(estimateShape(cl, resolution_, options_));
    if (!key) {
      key = next_track_++;
      tracks_[key] = Track{};
    }
    touched.insert(key);
    auto& g = gained[key];
    for (const CellXY& c : cl) {
      g.push_back(cellKey(c.x, c.y));
      owner_[g.back()] = key;
    }
  }
  // Rebuild the touched tracks: kept cells (untouched by this scan's clusters) plus gains.
  for (const int key : touched) {
    Track& tr = tracks_[key];
    std::vector<CellKey> cells;
    for (const CellKey k : tr.cells) {
      if (visited.count(k) || !cells_.count(k)) continue;
      const auto it = owner_.find(k);
      if (it != owner_.end() && it->second == key) cells.push_back(k);
    }
    const auto g = gained.find(key);
    if (g != gained.end()) cells.insert(cells.end(), g->second.begin(), g->second.end());
    std::sort(cells.begin(), cells.end());
    tr.cells.swap(cells);
    refresh(tr, resolution_);
    tr.hugs_wall = false;
    const double reach = options_.wall_hug_distance + 2 * resolution_;  // noise cells left out
    for (std::size_t i = 0; i < tr.cells.size() && !tr.hugs_wall && reach > 0; ++i) {
      tr.hugs_wall = nearNotFree(map, cellOf(tr.cells[i]), reach);
    }
    touched_.insert(key);
  }
}

namespace {
constexpr std::size_t kFitPoints = 200;  // points a shape is fitted to, at most
}  // namespace

void ObjectTracker::refresh(Track& tr, double res) {
  if (tr.cells.empty()) return;
  std::vector<CellXY> xy;
  xy.reserve(tr.cells.size());
  for (const CellKey k : tr.cells) xy.push_back(cellOf(k));
  ShapeEstimate s = estimateShape(xy, res, options_);
  // The hit points in its cells, when there are enough, measure it to the centimetre.
  // A cluster longer than any object (a wall seen off by localisation) needs no finer size.
  if (s.length > options_.max_size) tr.points.clear();
  for (auto it = tr.points.begin(); it != tr.points.end();) {
    if (std::binary_search(tr.cells.begin(), tr.cells.end(), it->second.cell)) {
      ++it;
    } else {
      it = tr.points.erase(it);  // its cell left the object: a point of the past
    }
  }
  // At most kFitPoints, evenly through the bins, keep the fit's cost bounded.
  const std::size_t stride = tr.points.size() / kFitPoints + 1;
  std::vector<double> px, py;
  double gap = std::numeric_limits<double>::infinity();  // the nearest view's beam spacing
  std::size_t i = 0;
  for (const auto& kv : tr.points) {
    gap = std::min(gap, kv.second.gap);
    if (i++ % stride != 0) continue;
    px.push_back(kv.second.x);
    py.push_back(kv.second.y);
  }
  ShapeEstimate fine;
  if (estimatePointShape(px, py, gap, sensor_x_, sensor_y_, options_, fine)) {
    fine.cells = s.cells;  // the filters and the fading rule count cells
    fine.thickness = s.thickness;
    fine.length = s.length;
    s = fine;
  }
  // A fading object keeps the estimate made from the most cells: its last cells are a part.
  if (tr.id == 0 || s.cells >= tr.best_cells) {
    tr.shape = s;
    tr.best_cells = std::max(tr.best_cells, s.cells);
  }
}

bool ObjectTracker::passesFilters(const Track& tr) const {
  // A thin row of cells along a wall is the wall seen at a grazing angle (or off by
  // localisation), not an object: no cylinder or person shows a straight row that long.
  const bool wall_row = tr.hugs_wall && tr.shape.thickness < options_.thin_width &&
                        tr.shape.length >= options_.thin_length;
  return !wall_row && static_cast<int>(tr.cells.size()) >= options_.min_cells &&
         tr.shape.size >= options_.min_size && tr.shape.size <= options_.max_size;
}

int ObjectTracker::trackOf(int id) const {
  for (const auto& kv : tracks_) {
    if (kv.second.id == id) return kv.first;
  }
  return 0;
}

void ObjectTracker::emit(double t, std::size_t scan_index, const TrackedObject& o, ObjectEvent e) {
  events_.push_back({t, scan_index, o.id, e, o.shape.cx, o.shape.cy, o.shape.size});
}

void ObjectTracker::dropLostTracks(double t, std::size_t scan_index) {
  for (const int key : touched_) {
    auto it = tracks_.find(key);
    if (it == tracks_.end() || !it->second.cells.empty()) continue;
    const Track& tr = it->second;
    // Cells fade only under beams that crossed them: the place was in view and seen free.
    if (tr.id && !tr.stale_of) {
      TrackedObject& o = object(tr.id);
      o.state = ObjectState::Absent;
      o.vanished_t = t;
      emit(t, scan_index, o, ObjectEvent::Disappeared);
    }
    pending_.erase(key);
    tracks_.erase(it);
  }
}

void ObjectTracker::checkStalePlaces(const ScanView& view, double t, std::size_t scan_index) {
  const double margin = std::max(0.05, 2 * resolution_);
  for (auto& kv : tracks_) {
    Track& tr = kv.second;
    if (!tr.stale_of) continue;
    const PlaceView pv = viewOf(view, tr.shape.cx, tr.shape.cy, 0.5 * tr.shape.size, margin);
    tr.seen_occupied = pv == PlaceView::SeenOccupied ? tr.seen_occupied + 1 : 0;
    // Seen occupied longer than D needs to fade a vacated cell: the object never left. If the
    // detection taken for it is still under its id, that was another object: it gets an id
    // of its own, and this one its id back.
    if (tr.seen_occupied <= options_.confirm_scans + 4) continue;
    const int id = tr.stale_of;
    const auto took = tracks_.find(tr.moved_to);
    if (took != tracks_.end() && took->second.id == id) {
      const int other = newObject(t);
      took->second.id = other;
      TrackedObject& o2 = object(other);
      o2.shape = took->second.shape;
      o2.last_seen_t = object(id).last_seen_t;
      o2.history.push_back({t, o2.shape.cx, o2.shape.cy});
      emit(t, scan_index, o2, ObjectEvent::New);
      TrackedObject& o = object(id);
      o.n_moves = std::max(0, o.n_moves - 1);  // the move was not one
      o.shape = tr.shape;
      o.state = ObjectState::Present;
      o.last_seen_t = t;
      o.history.push_back({t, o.shape.cx, o.shape.cy});
      tr.id = id;
      tr.stale_of = 0;
      tr.moved_to = 0;
      tr.anchor_x = tr.shape.cx;
      tr.anchor_y = tr.shape.cy;
      emit(t, scan_index, o, ObjectEvent::Reappeared);
      continue;
    }
    tr.exclude_id = tr.stale_of;  // it has moved on since: this is a new object
    tr.stale_of = 0;
    tr.passes = 0;
    tr.best_cells = 0;
    pending_.insert(kv.first);
  }
}

void ObjectTracker::confirmTentatives(const ScanView& view, double t, std::size_t scan_index) {
  std::set<int> candidates = pending_;
  for (const int key : touched_) candidates.insert(key);
  for (const int key : candidates) {
    auto it = tracks_.find(key);
    if (it == tracks_.end()) {
      pending_.erase(key);
      continue;
    }
    Track& tr = it->second;
    if (tr.id || tr.stale_of) {
      pending_.erase(key);
      continue;
    }
    if (!passesFilters(tr)) {
      tr.passes = 0;
      pending_.erase(key);
      continue;
    }
    pending_.insert(key);
    if (tr.passes == 0) tr.first_t = t;
    // Count only scans that left its size as it was: an object is judged once its size has
    // settled (it is all there, and the robot has seen enough of it to tell its size).
    const bool settled = std::abs(tr.shape.size - tr.last_size) <= options_.settle_size;
    tr.last_size = tr.shape.size;
    if (!settled) {
      tr.passes = 1;
    } else {
      ++tr.passes;
    }
    if (tr.passes >= options_.confirm_scans && confirm(key, view, t, scan_index)) {
      pending_.erase(key);
    }
  }
}

int ObjectTracker::newObject(double t) {
  TrackedObject o;
  o.id = static_cast<int>(objects_.size()) + 1;
  o.label = "object" + std::to_string(o.id);
  o.first_seen_t = t;
  objects_.push_back(o);
  return o.id;
}

bool ObjectTracker::confirm(int key, const ScanView& view, double t, std::size_t scan_index) {
  Track& tr = tracks_[key];
  const double margin = std::max(0.05, 2 * resolution_);
  std::vector<IdentityCandidate> cands;
  std::vector<int> ids;
  for (const TrackedObject& o : objects_) {
    if (o.id == tr.exclude_id) continue;
    const bool absent = o.state == ObjectState::Absent;
    const double dist = std::hypot(o.shape.cx - tr.shape.cx, o.shape.cy - tr.shape.cy);
    // A present object right here would have been followed, not re-found.
    if (!absent && dist <= options_.reappear_distance) continue;
    PlaceView pv = PlaceView::NotInView;
    if (!absent) pv = viewOf(view, o.shape.cx, o.shape.cy, 0.5 * o.shape.size, margin);
    // Seen in place a moment ago and not seen gone since: it did not cross the room unseen.
    if (!absent && pv != PlaceView::SeenFree && t - o.last_seen_t < options_.min_unseen_s) {
      continue;
    }
    cands.push_back({o.shape.cx, o.shape.cy, o.shape.size, absent, o.vanished_t, pv});
    ids.push_back(o.id);
  }
  const int pick = chooseIdentity(tr.shape, t, cands, options_);

  ObjectEvent ev = ObjectEvent::New;
  int id = 0;
  if (pick < 0) {
    id = newObject(t);
  } else {
    id = ids[static_cast<std::size_t>(pick)];
    TrackedObject& o = object(id);
    const double dist = std::hypot(o.shape.cx - tr.shape.cx, o.shape.cy - tr.shape.cy);
    // Only an object still shown at a place out of sight fits: wait until that place is seen
    // (free: it moved here; occupied: this is another object), for at most defer_s.
    if (o.state == ObjectState::Present && t - tr.first_t < options_.defer_s) return false;
    if (o.state == ObjectState::Present) {
      // Its old place was not seen vacated: keep those cells as a stale place to check.
      const int old = trackOf(id);
      if (old) {
        Track& st = tracks_[old];
        st.id = 0;
        st.stale_of = id;
        st.moved_to = key;
        st.seen_occupied = 0;
      }
      ev = ObjectEvent::Moved;
    } else {
      ev = dist <= options_.reappear_distance ? ObjectEvent::Reappeared : ObjectEvent::Moved;
    }
    if (ev == ObjectEvent::Moved) ++o.n_moves;
  }
  TrackedObject& o = object(id);
  tr.id = id;
  tr.best_cells = tr.shape.cells;
  tr.anchor_x = tr.shape.cx;
  tr.anchor_y = tr.shape.cy;
  o.shape = tr.shape;
  o.state = ObjectState::Present;
  o.last_seen_t = t;
  o.history.push_back({t, o.shape.cx, o.shape.cy});
  emit(t, scan_index, o, ev);
  return true;
}

void ObjectTracker::checkDrift(double t, std::size_t scan_index) {
  for (const int key : touched_) {
    auto it = tracks_.find(key);
    if (it == tracks_.end()) continue;
    Track& tr = it->second;
    if (!tr.id || tr.cells.empty()) continue;
    TrackedObject& o = object(tr.id);
    o.shape = tr.shape;
    if (std::hypot(tr.shape.cx - tr.anchor_x, tr.shape.cy - tr.anchor_y) > options_.move_distance) {
      tr.anchor_x = tr.shape.cx;
      tr.anchor_y = tr.shape.cy;
      ++o.n_moves;
      o.history.push_back({t, o.shape.cx, o.shape.cy});
      emit(t, scan_index, o, ObjectEvent::Moved);
    }
  }
}

void ObjectTracker::collectPoints(const DynamicGridMap& map, const ScanView& view) {
  if (view.empty() || owner_.empty()) return;
  const double bin = 0.01;  // [m] one point kept per bin: the latest
  std::set<int> fed;
  const std::size_t n = view.ranges.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double r = view.ranges[i];
    if (r <= 0.0 || r >= view.max_range) continue;
    const double a = view.phi + view.dir * (view.first + view.step * static_cast<double>(i));
    const double x = view.x + r * std::cos(a), y = view.y + r * std::sin(a);
    const int cx = map.x2idx(x), cy = map.y2idx(y);
    if (cx < 0 || cy < 0 || cx >= static_cast<int>(map.getSizeX()) ||
        cy >= static_cast<int>(map.getSizeY())) {
      continue;
    }
    const CellKey cell = cellKey(cx + origin_x_, cy + origin_y_);
    const auto it = owner_.find(cell);
    if (it == owner_.end() || !cells_.count(cell)) continue;
    const CellKey b =
        cellKey(static_cast<int>(std::floor(x / bin)), static_cast<int>(std::floor(y / bin)));
    Track& tr = tracks_[it->second];
    if (tr.shape.length > options_.max_size) continue;  // a wall: no finer size needed
    auto& points = tr.points;
    const bool fresh = points.find(b) == points.end();
    points[b] = {x, y, r * std::abs(view.step), cell};
    if (fresh) fed.insert(it->second);  // a point where none was: the arc grew
  }
  for (const int key : fed) {
    refresh(tracks_[key], resolution_);
    touched_.insert(key);  // a better size may now pass the filters
  }
}

void ObjectTracker::updateLastSeen(const ScanView& view, double t) {
  if (view.empty()) return;
  const double margin = std::max(0.05, 2 * resolution_);
  for (TrackedObject& o : objects_) {
    if (o.state != ObjectState::Present) continue;
    if (viewOf(view, o.shape.cx, o.shape.cy, 0.5 * o.shape.size, margin) ==
        PlaceView::SeenOccupied) {
      o.last_seen_t = t;
    }
  }
}

}  // namespace dynamap
