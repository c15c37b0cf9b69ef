#include "dynamap/people/leg_features.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace dynamap {

ScanHits polarScanHits(double angle_min, double increment, const std::vector<float>& ranges,
                       double range_min, double range_max) {
  ScanHits h;
  h.max_range = range_max;
  h.step = std::abs(increment);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const double a = angle_min + increment * static_cast<double>(i);
    const float r = ranges[i];
    // A range at range_max is the sensor's "nothing" on many lasers.
    const bool echo = std::isfinite(r) && r >= range_min && r < range_max;
    h.angles.push_back(a);
    h.cosines.push_back(std::cos(a));
    h.sines.push_back(std::sin(a));
    h.ranges.push_back(echo ? r : -1.0f);
    if (echo) h.points.push_back({r * h.cosines.back(), r * h.sines.back(), i});
  }
  return h;
}

std::vector<Segment> segmentScan(const ScanHits& hits, double jump, std::size_t min_points,
                                 std::size_t max_gap) {
  std::vector<Segment> out;
  const std::vector<HitPoint2>& p = hits.points;
  std::size_t begin = 0;
  const double jump2 = jump * jump;  // squared distances: hypot costs more than the rest
  for (std::size_t i = 1; i <= p.size(); ++i) {
    const auto far = [&] {
      const double dx = p[i].x - p[i - 1].x, dy = p[i].y - p[i - 1].y;
      return dx * dx + dy * dy > jump2;
    };
    const bool split = i == p.size() || p[i].beam > p[i - 1].beam + max_gap + 1 || far();
    if (!split) continue;
    if (i - begin >= min_points) out.push_back({begin, i});
    begin = i;
  }
  return out;
}

const std::array<const char*, kLegFeatureCount>& legFeatureNames() {
  static const std::array<const char*, kLegFeatureCount> names = {
      "points",        "spread",          "median_deviation", "width",
      "linearity",     "circularity",     "radius",           "boundary_length",
      "boundary_regularity", "mean_curvature", "mean_turn",   "inscribed_angle",
      "inscribed_angle_std", "distance",  "beam_spacing",     "occluded_before",
      "occluded_after"};
  return names;
}

namespace {

// What one call works in, kept per thread between calls: a scan classifies a few dozen
// segments, and allocating these for each was most of the features' cost.
struct Scratch {
  std::vector<Eigen::Vector2d> p;
  std::vector<double> xs, ys, steps, turns, curvatures, inscribed;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// The points of a segment relative to their mean (into `p`): a map's coordinates are tens of
// metres, a leg's a few centimetres, and the fits below square them.
Eigen::Vector2d centred(const ScanHits& h, const Segment& s, std::vector<Eigen::Vector2d>& p) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t i = s.begin; i < s.end; ++i) mean += Eigen::Vector2d(h.points[i].x, h.points[i].y);
  mean /= static_cast<double>(s.size());
  p.clear();
  for (std::size_t i = s.begin; i < s.end; ++i)
    p.emplace_back(h.points[i].x - mean.x(), h.points[i].y - mean.y());
  return mean;
}

// The median of `v` (reordered): the mean of its two middle values when their count is even.
double median(std::vector<double>& v) {
  const std::size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  const double upper = v[n / 2];
  if (n % 2 == 1) return upper;
  return 0.5 * (*std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2)) + upper);
}

// The median of x and of y, each on its own (robust to a stray point at an end).
Eigen::Vector2d medianPoint(const std::vector<Eigen::Vector2d>& p, Scratch& w) {
  w.xs.clear();
  w.ys.clear();
  for (const auto& q : p) w.xs.push_back(q.x()), w.ys.push_back(q.y());
  return {median(w.xs), median(w.ys)};
}

// Circle through the points by least squares on x^2 + y^2 = 2 a x + 2 b y + c: its radius (at
// most 2 m: a straight run has an "infinite" one) and the mean squared distance to it. Matrix
// is a fixed-capacity type for the usual segment, a heap-allocated one for a long one.
template <typename Matrix, typename Vector>
std::pair<double, double> circleFit(const std::vector<Eigen::Vector2d>& p) {
  Matrix a(static_cast<Eigen::Index>(p.size()), 3);
  Vector b(static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) << 2 * p[i].x(), 2 * p[i].y(), 1.0;
    b(static_cast<Eigen::Index>(i)) = p[i].squaredNorm();
  }
  const Eigen::Vector3d sol = a.colPivHouseholderQr().solve(b);
  const double r2 = sol(0) * sol(0) + sol(1) * sol(1) + sol(2);
  constexpr double kMaxRadius = 2.0;
  double r = r2 > 0 && std::isfinite(r2) ? std::sqrt(r2) : kMaxRadius;
  const Eigen::Vector2d centre(sol(0), sol(1));
  const bool capped = !(r < kMaxRadius) || !centre.allFinite();
  r = std::min(r, kMaxRadius);
  double sq = 0;
  for (const auto& q : p) {
    // A capped circle is too flat to tell from a line: its residual is the line's, below.
    const double d = capped ? 0.0 : (q - centre).norm() - r;
    sq += d * d;
  }
  return {r, capped ? -1.0 : sq / static_cast<double>(p.size())};
}

std::pair<double, double> circleFit(const std::vector<Eigen::Vector2d>& p) {
  constexpr int kFixed = 96;
  if (p.size() <= static_cast<std::size_t>(kFixed)) {
    return circleFit<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, kFixed, 3>,
                     Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kFixed, 1>>(p);
  }
  return circleFit<Eigen::MatrixXd, Eigen::VectorXd>(p);
}

// The angle at m from the ray towards a to the ray towards b, in [0, 2 pi).
double angleAt(const Eigen::Vector2d& a, const Eigen::Vector2d& m, const Eigen::Vector2d& b) {
  const Eigen::Vector2d u = a - m, v = b - m;
  double th = std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
  return th < 0 ? th + 2 * M_PI : th;
}

double meanOf(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

double stdOf(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = meanOf(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// Features 7-12: the boundary's steps, turns, curvature and inscribed angles.
void boundaryFeatures(const std::vector<Eigen::Vector2d>& p, Scratch& w, LegFeatures& f) {
  std::vector<double>&steps = w.steps, &turns = w.turns, &curvatures = w.curvatures,
  &inscribed = w.inscribed;
  steps.clear(), turns.clear(), curvatures.clear(), inscribed.clear();
  for (std::size_t i = 1; i < p.size(); ++i) steps.push_back((p[i] - p[i - 1]).norm());
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double th = angleAt(p[i - 1], p[i], p[i + 1]);
    turns.push_back(th);
    const double a = steps[i - 1], b = steps[i], c = (p[i + 1] - p[i - 1]).norm();
    const double cross = (p[i] - p[i - 1]).x() * (p[i + 1] - p[i]).y() -
                         (p[i] - p[i - 1]).y() * (p[i + 1] - p[i]).x();
    // 4 * area / (a b c) is 1 / the radius of the circle through the three points.
    const double k = a * b * c > 1e-12 ? 2.0 * std::abs(cross) / (a * b * c) : 0.0;
    curvatures.push_back(cross >= 0 ? k : -k);
    inscribed.push_back(angleAt(p.front(), p[i], p.back()));
  }
  double length = 0;
  for (double s : steps) length += s;
  f[7] = static_cast<float>(length);
  f[8] = static_cast<float>(stdOf(steps));
  f[9] = static_cast<float>(meanOf(curvatures));
  f[10] = static_cast<float>(meanOf(turns));
  f[11] = static_cast<float>(meanOf(inscribed));
  f[12] = static_cast<float>(stdOf(inscribed));
}

// Whether beam `beam` (when in the scan) ends nearer the sensor than `range`.
float occludedBy(const ScanHits& h, std::ptrdiff_t beam, double range) {
  if (beam < 0 || beam >= static_cast<std::ptrdiff_t>(h.ranges.size())) return 0.0f;
  const float r = h.ranges[static_cast<std::size_t>(beam)];
  return r >= 0 && r < range ? 1.0f : 0.0f;
}

}  // namespace

LegFeatures legFeatures(const ScanHits& h, const Segment& s) {
  LegFeatures f{};
  Scratch& w = scratch();
  const Eigen::Vector2d mean = centred(h, s, w.p);
  const std::vector<Eigen::Vector2d>& p = w.p;
  const double n = static_cast<double>(p.size());
  const Eigen::Vector2d med = medianPoint(p, w);
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  double dev = 0;
  for (const auto& q : p) {
    cov += q * q.transpose();
    dev += (q - med).norm();
  }
  f[0] = static_cast<float>(n);
  f[1] = static_cast<float>(std::sqrt(cov.trace() / std::max(1.0, n - 1)));
  f[2] = static_cast<float>(dev / n);
  f[3] = static_cast<float>((p.back() - p.front()).norm());
  // The smaller eigenvalue of the scatter: the points' mean squared distance to their best line.
  const double linearity = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov / n).eigenvalues()(0);
  f[4] = static_cast<float>(std::max(0.0, linearity));
  const auto [radius, circ] = circleFit(p);
  f[5] = static_cast<float>(circ < 0 ? f[4] : circ);
  f[6] = static_cast<float>(radius);
  boundaryFeatures(p, w, f);
  const Eigen::Vector2d sensor(h.sensor_x, h.sensor_y);
  const double distance = (mean + med - sensor).norm();
  f[13] = static_cast<float>(distance);
  f[14] = static_cast<float>(distance * h.step);
  const HitPoint2 &first = h.points[s.begin], &last = h.points[s.end - 1];
  f[15] = occludedBy(h, static_cast<std::ptrdiff_t>(first.beam) - 1,
                     std::hypot(first.x - h.sensor_x, first.y - h.sensor_y));
  f[16] = occludedBy(h, static_cast<std::ptrdiff_t>(last.beam) + 1,
                     std::hypot(last.x - h.sensor_x, last.y - h.sensor_y));
  return f;
}

}  // namespace dynamap
