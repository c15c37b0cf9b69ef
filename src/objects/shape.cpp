#include "dynamap/objects/shape.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace dynamap {

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
// Moves `c` (from a free fit) to the centre that best puts the points at distance r from it.
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

// The box of the first n points.
struct Extent {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
};
Extent extentOf(const std::vector<double>& xs, const std::vector<double>& ys, std::size_t n) {
  Extent e;
  for (std::size_t i = 0; i < n; ++i) {
    e.x0 = std::min(e.x0, xs[i]);
    e.x1 = std::max(e.x1, xs[i]);
    e.y0 = std::min(e.y0, ys[i]);
    e.y1 = std::max(e.y1, ys[i]);
  }
  return e;
}

// The widest distance between the first n points (the visible outline of a convex object is as
// wide as the object). It joins two corners of their convex hull: O(n log n) for the hull, then
// pairs of its few corners.
double widestChord(const std::vector<double>& xs, const std::vector<double>& ys, std::size_t n) {
  const std::vector<std::size_t> hull = convexHull(xs, ys, n);
  double width2 = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    for (std::size_t j = i + 1; j < hull.size(); ++j) {
      const double dx = xs[hull[i]] - xs[hull[j]], dy = ys[hull[i]] - ys[hull[j]];
      width2 = std::max(width2, dx * dx + dy * dy);
    }
  }
  return std::sqrt(width2);
}

// Makes `s` the circle of diameter `size` centred on (cx, cy), its box included.
void setCircle(ShapeEstimate& s, double cx, double cy, double size) {
  s.circle = true;
  s.cx = cx;
  s.cy = cy;
  s.size = size;
  s.x_min = cx - 0.5 * size;
  s.x_max = cx + 0.5 * size;
  s.y_min = cy - 0.5 * size;
  s.y_max = cy + 0.5 * size;
}

// Two half diagonals of a cell: how much farther apart two cell centres can lie than the points
// of a surface that marked them (a ring of cells seen all round is that much wider).
constexpr double kHalfDiagonals = 1.41421356237309515;

// The circle fit of estimateShape's cell centres, into `s` when it is sane.
bool cellCircle(const std::vector<double>& xs, const std::vector<double>& ys, double width,
                double res, const ObjectOptions& options, ShapeEstimate& s) {
  Circle c{};
  // (No circle for what is wider than any object: a wall.)
  if (static_cast<int>(xs.size()) < options.min_fit_cells || width > options.max_size ||
      !fitCircle(xs, ys, c)) {
    return false;
  }
  double d = 2 * c.r;
  // Sane: as wide as the cells at least (less their quantisation: a cell's centre lies up to
  // half its diagonal off the surface that marked it, on either side), not much wider than
  // them (a short arc of a huge circle is a wall, not a cylinder), within max_size.
  if (!(d >= width - kHalfDiagonals * res && d <= 1.6 * (width + res) && d <= options.max_size))
    return false;
  // An arc of grid cells looks flatter than the surface: the fit overshoots, while a convex
  // object's outline is exactly as wide as the object. Keep the smaller, and centre the circle
  // of that size on the cells.
  if (d > width + res) {
    d = width + res;
    fitCentre(xs, ys, 0.5 * d, c);
  }
  setCircle(s, c.cx, c.cy, d);
  return true;
}

// The root mean square distance of the first n points from circle c.
double circleRms(const std::vector<double>& xs, const std::vector<double>& ys, std::size_t n,
                 const Circle& c) {
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ex = xs[i] - c.cx, ey = ys[i] - c.cy;
    const double e = std::sqrt(ex * ex + ey * ey) - c.r;
    rss += e * e;
  }
  return std::sqrt(rss / static_cast<double>(n));
}

// The circle fit of estimatePointShape's n hit points (mean (mx, my)), into `s` when sane.
bool pointCircle(const std::vector<double>& xs, const std::vector<double>& ys, std::size_t n,
                 double width, double mx, double my, double sensor_x, double sensor_y,
                 const ObjectOptions& options, ShapeEstimate& s) {
  Circle c{};
  if (!fitCircle(xs, ys, c)) return false;
  const double d = 2 * c.r;
  const double rms = circleRms(xs, ys, n, c);
  // Sane: the points span a few centimetres of arc at least, lie on it (range noise of a
  // centimetre or two), it is no narrower than they are and not far wider (a short flat arc
  // fits any large circle), and it bulges towards the sensor, as a solid seen from outside
  // does: its centre lies beyond the points.
  const bool beyond =
      std::hypot(c.cx - sensor_x, c.cy - sensor_y) > std::hypot(mx - sensor_x, my - sensor_y);
  if (!(width >= 0.04 && rms <= 0.02 && d >= width - 0.02 &&
        d <= std::max(1.5 * width, width + 0.06) && d <= options.max_size && beyond)) {
    return false;
  }
  setCircle(s, c.cx, c.cy, std::max(d, width));
  return true;
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
  for (const CellXY& c : cells) {
    xs.push_back((c.x + 0.5) * res);
    ys.push_back((c.y + 0.5) * res);
  }
  const Extent e = extentOf(xs, ys, xs.size());
  const double width = widestChord(xs, ys, xs.size());
  s.thickness = minorAxisStd(xs, ys);
  s.length = width;
  if (cellCircle(xs, ys, width, res, options, s)) return s;
  // The widest extent plus a cell (each end cell is covered whole), centred on the cells' box.
  s.size = width + res;
  s.cx = 0.5 * (e.x0 + e.x1);
  s.cy = 0.5 * (e.y0 + e.y1);
  s.x_min = e.x0 - 0.5 * res;
  s.x_max = e.x1 + 0.5 * res;
  s.y_min = e.y0 - 0.5 * res;
  s.y_max = e.y1 + 0.5 * res;
  return s;
}

bool estimatePointShape(const std::vector<double>& xs, const std::vector<double>& ys, double gap,
                        double sensor_x, double sensor_y, const ObjectOptions& options,
                        ShapeEstimate& out) {
  const std::size_t n = std::min(xs.size(), ys.size());
  if (n == 0 || static_cast<int>(n) < options.min_fit_cells) return false;
  const Extent e = extentOf(xs, ys, n);
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) mx += xs[i], my += ys[i];
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  const double width = widestChord(xs, ys, n);
  ShapeEstimate s;
  s.cells = n;
  s.length = width;
  s.thickness = minorAxisStd(xs, ys);
  if (!pointCircle(xs, ys, n, width, mx, my, sensor_x, sensor_y, options, s)) {
    // Each edge lies somewhere between the last beam that hit and the first that missed.
    s.size = width + gap;
    s.cx = 0.5 * (e.x0 + e.x1);
    s.cy = 0.5 * (e.y0 + e.y1);
    s.x_min = std::min(e.x0, s.cx - 0.5 * s.size);
    s.x_max = std::max(e.x1, s.cx + 0.5 * s.size);
    s.y_min = std::min(e.y0, s.cy - 0.5 * s.size);
    s.y_max = std::max(e.y1, s.cy + 0.5 * s.size);
  }
  out = s;
  return true;
}

}  // namespace dynamap
