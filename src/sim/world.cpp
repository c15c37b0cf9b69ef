#include "dynamap/sim/world.h"

#include <algorithm>
#include <cmath>

namespace dynamap::sim {
namespace {

double cross(Vec2 a, Vec2 b) {
  return a.x * b.y - a.y * b.x;
}
double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
Vec2 sub(Vec2 a, Vec2 b) {
  return {a.x - b.x, a.y - b.y};
}

// Parameter interval [t0, t1] of the ray inside the box [0, w] × [0, h] (cell units), by slabs.
bool clipToBox(Vec2 o, Vec2 d, double w, double h, double& t0, double& t1) {
  t0 = 0;
  t1 = kNoHit;
  const double lo[2] = {0, 0}, hi[2] = {w, h}, oo[2] = {o.x, o.y}, dd[2] = {d.x, d.y};
  for (int k = 0; k < 2; ++k) {
    if (dd[k] == 0) {
      if (oo[k] < lo[k] || oo[k] >= hi[k]) return false;
      continue;
    }
    double a = (lo[k] - oo[k]) / dd[k], b = (hi[k] - oo[k]) / dd[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 < t1;
}

// One axis of the grid walk: the step, the ray parameter of the next boundary, the increment.
struct Axis {
  int step = 0;
  double t_next = kNoHit;
  double t_delta = kNoHit;
};

Axis makeAxis(double o, double d, int cell) {
  Axis a;
  if (d > 0) a = {1, (cell + 1 - o) / d, 1 / d};
  if (d < 0) a = {-1, (cell - o) / d, -1 / d};
  return a;
}

}  // namespace

double distance(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

double raySegment(Vec2 o, Vec2 d, const Segment& s) {
  const Vec2 e = sub(s.b, s.a);
  const double denom = cross(d, e);
  if (denom == 0) return kNoHit;  // parallel or collinear: no surface faces the beam
  const Vec2 w = sub(s.a, o);
  const double t = cross(w, e) / denom;
  const double u = cross(w, d) / denom;
  if (t < 0 || u < 0 || u > 1) return kNoHit;
  return t;
}

double rayCircle(Vec2 o, Vec2 d, Vec2 centre, double radius) {
  const Vec2 oc = sub(o, centre);
  const double b = dot(d, oc);
  const double c = dot(oc, oc) - radius * radius;
  if (c <= 0) return kNoHit;  // inside (or on) the circle
  if (b >= 0) return kNoHit;  // the circle lies behind the origin
  const double disc = b * b - c;
  if (disc < 0) return kNoHit;
  // t = -b - sqrt(disc) loses digits when disc ≈ b²; the product of the roots is c, so the near
  // root is c / (far root), which has no cancellation.
  return c / (-b + std::sqrt(disc));
}

double rayGrid(Vec2 o, Vec2 d, double max_range, const WallGrid& grid) {
  if (grid.width <= 0 || grid.height <= 0) return kNoHit;
  const double res = grid.resolution;
  const Vec2 g{(o.x - grid.origin.x) / res, (o.y - grid.origin.y) / res};  // in cells
  double t = 0, t_exit = 0;
  if (!clipToBox(g, d, grid.width, grid.height, t, t_exit)) return kNoHit;
  const double t_max = std::min(t_exit, max_range / res);
  int ix = std::clamp(static_cast<int>(std::floor(g.x + t * d.x)), 0, grid.width - 1);
  int iy = std::clamp(static_cast<int>(std::floor(g.y + t * d.y)), 0, grid.height - 1);
  Axis ax = makeAxis(g.x, d.x, ix), ay = makeAxis(g.y, d.y, iy);
  while (t <= t_max) {
    if (grid.isWall(ix, iy)) return t * res;
    if (ax.t_next < ay.t_next) {
      t = ax.t_next;
      ix += ax.step;
      ax.t_next += ax.t_delta;
    } else {
      t = ay.t_next;
      iy += ay.step;
      ay.t_next += ay.t_delta;
    }
    if (ix < 0 || iy < 0 || ix >= grid.width || iy >= grid.height) return kNoHit;
  }
  return kNoHit;
}

RayHit castRay(const StaticWorld& world, const std::vector<Body>& bodies, Vec2 o, double angle,
               double max_range) {
  const Vec2 d{std::cos(angle), std::sin(angle)};
  RayHit best;
  auto consider = [&](double t, int body) {
    if (t <= max_range && t < best.range) best = {t, body};
  };
  for (const auto& s : world.segments) consider(raySegment(o, d, s), -1);
  consider(rayGrid(o, d, max_range, world.grid), -1);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    consider(rayCircle(o, d, bodies[i].centre, bodies[i].radius), static_cast<int>(i));
  }
  return best;
}

double pointSegmentDistance(Vec2 p, const Segment& s) {
  const Vec2 e = sub(s.b, s.a);
  const double len2 = dot(e, e);
  if (len2 == 0) return distance(p, s.a);
  const double u = std::clamp(dot(sub(p, s.a), e) / len2, 0.0, 1.0);
  return distance(p, {s.a.x + u * e.x, s.a.y + u * e.y});
}

bool segmentsIntersect(const Segment& s, const Segment& t) {
  const auto orient = [](Vec2 a, Vec2 b, Vec2 c) {
    const double v = cross(sub(b, a), sub(c, a));
    return (v > 0) - (v < 0);
  };
  const auto onSegment = [](Vec2 a, Vec2 b, Vec2 p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
  };
  const int o1 = orient(s.a, s.b, t.a), o2 = orient(s.a, s.b, t.b);
  const int o3 = orient(t.a, t.b, s.a), o4 = orient(t.a, t.b, s.b);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && onSegment(s.a, s.b, t.a)) || (o2 == 0 && onSegment(s.a, s.b, t.b)) ||
         (o3 == 0 && onSegment(t.a, t.b, s.a)) || (o4 == 0 && onSegment(t.a, t.b, s.b));
}

bool discOverlapsSegment(Vec2 centre, double radius, const Segment& s) {
  return pointSegmentDistance(centre, s) < radius;
}

bool discOverlapsGrid(Vec2 centre, double radius, const WallGrid& grid) {
  if (grid.width <= 0) return false;
  const double res = grid.resolution;
  const int x0 =
      std::max(0, static_cast<int>(std::floor((centre.x - radius - grid.origin.x) / res)));
  const int x1 = std::min(grid.width - 1,
                          static_cast<int>(std::floor((centre.x + radius - grid.origin.x) / res)));
  const int y0 =
      std::max(0, static_cast<int>(std::floor((centre.y - radius - grid.origin.y) / res)));
  const int y1 = std::min(grid.height - 1,
                          static_cast<int>(std::floor((centre.y + radius - grid.origin.y) / res)));
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      if (!grid.isWall(ix, iy)) continue;
      const double cx0 = grid.origin.x + ix * res, cy0 = grid.origin.y + iy * res;
      const double dx = std::max({cx0 - centre.x, 0.0, centre.x - (cx0 + res)});
      const double dy = std::max({cy0 - centre.y, 0.0, centre.y - (cy0 + res)});
      if (std::hypot(dx, dy) < radius) return true;
    }
  }
  return false;
}

bool segmentCrossesGrid(const Segment& s, const WallGrid& grid) {
  const double len = distance(s.a, s.b);
  if (len == 0) return rayGrid(s.a, {1, 0}, 0, grid) == 0;
  const Vec2 d{(s.b.x - s.a.x) / len, (s.b.y - s.a.y) / len};
  return rayGrid(s.a, d, len, grid) != kNoHit;
}

}  // namespace dynamap::sim
