#include "dynamap/objects/scan_view.h"

#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>

#include "dynamap/base/angles.h"

namespace dynamap {

ScanView makeScanView(const RangeData& rd, const mrpt::poses::CPose2D& robot) {
  ScanView v;
  const std::size_t n = rd.size();
  if (n == 0) return v;
  const mrpt::poses::CPose2D sensor = rd.sensorIn(mrpt::poses::CPose3D(robot));
  v.x = sensor.x();
  v.y = sensor.y();
  v.phi = sensor.phi();
  v.first = rd.first;
  v.step = rd.step;
  v.dir = rd.dir;
  v.max_range = rd.insertion_range;
  v.ranges.resize(n);
  if (rd.cos_angle.size() == n && rd.sin_angle.size() == n) {
    const double c = std::cos(v.phi), s = std::sin(v.phi);
    v.cosines.resize(n);
    v.sines.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      v.cosines[i] = c * rd.cos_angle[i] - s * rd.sin_angle[i];
      v.sines[i] = s * rd.cos_angle[i] + c * rd.sin_angle[i];
    }
  }
  const float cut = static_cast<float>(rd.insertion_range);
  for (std::size_t i = 0; i < n; ++i) {
    const bool echo = rd.kinds[i] == BeamKind::Hit || rd.kinds[i] == BeamKind::Beyond;
    v.ranges[i] = echo ? std::min(rd.ranges[i], cut) : -1.0f;
  }
  return v;
}

PlaceView viewOf(const ScanView& v, double cx, double cy, double r, double margin,
                 const std::function<bool(std::size_t)>& on_wall) {
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
    const double off = wrapAngle(beamAngle(v, static_cast<std::size_t>(i)) - bearing);
    const double along = d * std::cos(off), perp = d * std::abs(std::sin(off));
    if (perp > r) continue;
    const double entry = along - std::sqrt(r * r - perp * perp);
    if (range < entry - margin) continue;  // hidden behind something nearer
    if (range <= entry + margin) {
      if (on_wall && on_wall(static_cast<std::size_t>(i))) continue;
      ++seen_occupied;
    } else {
      ++seen_free;  // the beam went past where the object's surface would be
    }
  }
  if (seen_occupied > 0 && seen_occupied >= seen_free) return PlaceView::SeenOccupied;
  if (seen_free > 0) return PlaceView::SeenFree;
  return PlaceView::NotInView;
}

namespace {

bool hasHit(const ScanView& v, long i) {
  return v.ranges[static_cast<std::size_t>(i)] >= 0 &&
         v.ranges[static_cast<std::size_t>(i)] < v.max_range;
}

// Extends the run from `from` one way (`dir` = ±1); true when its end is an outline edge.
bool extendRun(const ScanView& v, long from, long dir, double jump, long& end) {
  const long n = static_cast<long>(v.ranges.size());
  end = from;
  for (long i = from + dir; i >= 0 && i < n; i += dir) {
    if (!hasHit(v, i)) return true;  // no echo beside it: seen against nothing
    const double step =
        v.ranges[static_cast<std::size_t>(i)] - v.ranges[static_cast<std::size_t>(end)];
    if (step > jump) return true;    // the next beam passes behind it
    if (step < -jump) return false;  // something nearer hides the rest
    end = i;
  }
  return false;  // the field of view cuts it
}

}  // namespace

BeamRun beamRunAround(const ScanView& v, std::size_t beam, double jump) {
  BeamRun run;
  long lo = static_cast<long>(beam), hi = lo;
  run.edge_before = extendRun(v, lo, -1, jump, lo);
  run.edge_after = extendRun(v, hi, 1, jump, hi);
  run.first = static_cast<std::size_t>(lo);
  run.last = static_cast<std::size_t>(hi);
  return run;
}

void hitPoint(const ScanView& v, std::size_t i, double& x, double& y) {
  const double a = beamAngle(v, i);
  x = v.x + v.ranges[i] * std::cos(a);
  y = v.y + v.ranges[i] * std::sin(a);
}

}  // namespace dynamap
