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

}  // namespace dynamap
