#include "dynamap/sim/added_objects.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "dynamap/base/angles.h"
#include "dynamap/sim/random.h"

namespace dynamap::sim {

namespace {

double number(const std::string& key, const std::string& value) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || value.empty() || !std::isfinite(v)) {
    throw std::invalid_argument(key + ": not a number: '" + value + "'");
  }
  return v;
}

int count(const std::string& key, const std::string& value, int lo, int hi) {
  const double v = number(key, value);
  if (v != std::floor(v) || v < lo || v > hi) {
    throw std::invalid_argument(key + ": expected a whole number in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + value + "'");
  }
  return static_cast<int>(v);
}

double inRange(const std::string& key, const std::string& value, double lo, double hi) {
  const double v = number(key, value);
  if (v < lo || v > hi) {
    std::ostringstream s;
    s << key << ": expected a value in [" << lo << ", " << hi << "], got '" << value << "'";
    throw std::invalid_argument(s.str());
  }
  return v;
}

void setKey(AddObjectsSpec& s, const std::string& key, const std::string& value) {
  if (key == "objects") {
    s.objects = count(key, value, 1, 20);
  } else if (key == "moves") {
    s.moves = count(key, value, 1, 200);
  } else if (key == "seed") {
    s.seed = static_cast<std::uint64_t>(count(key, value, 0, 1000000000));
  } else if (key == "sizes") {
    const auto dash = value.find('-', 1);
    if (dash == std::string::npos) throw std::invalid_argument("sizes: expected MIN-MAX (m)");
    s.min_diameter = inRange(key, value.substr(0, dash), 0.05, 2);
    s.max_diameter = inRange(key, value.substr(dash + 1), s.min_diameter, 2);
  } else if (key == "glide") {
    s.glide_s = inRange(key, value, 0, 30);
  } else if (key == "wall") {
    s.wall_clearance_m = inRange(key, value, 0, 5);
  } else if (key == "path") {
    s.path_clearance_m = inRange(key, value, 0, 5);
  } else if (key == "seen") {
    s.seen_scans = count(key, value, 1, 1000);
  } else if (key == "beams") {
    s.seen_beams = count(key, value, 1, 100);
  } else if (key == "window") {
    s.window_seen = count(key, value, 1, 1000);
  } else {
    throw std::invalid_argument("unknown key '" + key +
                                "' (objects, moves, seed, sizes, glide, wall, path, seen, beams, "
                                "window)");
  }
}

/// Chamfer distance (1, sqrt 2 cells) from the cells flagged in `seed`, capped at `cap` metres.
std::vector<float> chamfer(const std::vector<std::uint8_t>& seed, int nx, int ny, double res,
                           double cap) {
  std::vector<float> d(seed.size());
  for (std::size_t i = 0; i < seed.size(); ++i) d[i] = seed[i] ? 0.f : static_cast<float>(cap);
  const float a = static_cast<float>(res), b = static_cast<float>(res * std::sqrt(2.0));
  auto relax = [&](int x, int y, int dx, int dy, float w) {
    const int u = x + dx, v = y + dy;
    if (u < 0 || v < 0 || u >= nx || v >= ny) return;
    float& here = d[static_cast<std::size_t>(y) * nx + x];
    here = std::min(here, d[static_cast<std::size_t>(v) * nx + u] + w);
  };
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      relax(x, y, -1, 0, a), relax(x, y, 0, -1, a), relax(x, y, -1, -1, b), relax(x, y, 1, -1, b);
    }
  }
  for (int y = ny - 1; y >= 0; --y) {
    for (int x = nx - 1; x >= 0; --x) {
      relax(x, y, 1, 0, a), relax(x, y, 0, 1, a), relax(x, y, 1, 1, b), relax(x, y, -1, 1, b);
    }
  }
  return d;
}

/// Beam indices of `scan` that may meet the disc (empty range: first > last).
std::pair<long, long> beamWindow(const ScanGeometry& scan, Vec2 c, double r) {
  const double dx = c.x - scan.sensor.x, dy = c.y - scan.sensor.y, d = std::hypot(dx, dy);
  if (d <= r || d - r >= scan.max_range || scan.step <= 0 || scan.ranges.empty()) return {1, 0};
  const double rel = wrapAngle(std::atan2(dy, dx) - scan.sensor_phi - scan.first_angle - kPi) + kPi;
  const double half = std::asin(std::min(1.0, r / d));
  const long n = static_cast<long>(scan.ranges.size());
  const long lo = std::max(0L, static_cast<long>(std::ceil((rel - half) / scan.step)));
  const long hi = std::min(n - 1, static_cast<long>(std::floor((rel + half) / scan.step)));
  return {lo, hi};
}

double beamAngle(const ScanGeometry& scan, long i) {
  return scan.sensor_phi + scan.first_angle + static_cast<double>(i) * scan.step;
}

double beamDistance(const ScanGeometry& scan, long i, Vec2 c, double r) {
  const double a = beamAngle(scan, i);
  return rayCircle(scan.sensor, {std::cos(a), std::sin(a)}, c, r);
}

/// Per beam, the object (plan.objects index) it meets first before its own return, or -1; the
/// distance to it in `range`.
void owners(const AddedPlan& plan, const ScanGeometry& scan, std::vector<int>& owner,
            std::vector<double>& range) {
  owner.assign(scan.ranges.size(), -1);
  range.assign(scan.ranges.begin(), scan.ranges.end());
  for (std::size_t k = 0; k < plan.objects.size(); ++k) {
    const double r = plan.objects[k].diameter / 2;
    const Vec2 c = addedPositionAt(plan, k, scan.t);
    const auto [lo, hi] = beamWindow(scan, c, r);
    for (long i = lo; i <= hi; ++i) {
      const double d = beamDistance(scan, i, c, r);
      if (d < range[i]) range[i] = d, owner[i] = static_cast<int>(k);
    }
  }
}

/// The index in plan.objects of the object with id `id` (every move's object is there).
std::size_t objectIndexOf(const AddedPlan& plan, int id) {
  std::size_t k = 0;
  while (plan.objects[k].id != id) ++k;
  return k;
}

}  // namespace

AddObjectsSpec parseAddObjectsSpec(const std::string& text) {
  AddObjectsSpec s;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw std::invalid_argument("expected key=value, got '" + item + "'");
    }
    setKey(s, item.substr(0, eq), item.substr(eq + 1));
  }
  return s;
}

void FreeSpace::build(const std::vector<std::uint8_t>& free, const std::vector<Vec2>& robot,
                      double cap) {
  if (free.size() != static_cast<std::size_t>(size_x) * size_y) {
    throw std::invalid_argument("FreeSpace::build: one flag per cell expected");
  }
  std::vector<std::uint8_t> blocked(free.size()), path(free.size(), 0);
  for (std::size_t i = 0; i < free.size(); ++i) blocked[i] = free[i] ? 0 : 1;
  for (const Vec2& p : robot) {
    const int x = static_cast<int>(std::floor((p.x - x_min) / resolution));
    const int y = static_cast<int>(std::floor((p.y - y_min) / resolution));
    if (x >= 0 && y >= 0 && x < size_x && y < size_y)
      path[static_cast<std::size_t>(y) * size_x + x] = 1;
  }
  clearance = chamfer(blocked, size_x, size_y, resolution, cap);
  path_distance = chamfer(path, size_x, size_y, resolution, cap);
}

double FreeSpace::clearanceAt(Vec2 p) const {
  const int x = static_cast<int>(std::floor((p.x - x_min) / resolution));
  const int y = static_cast<int>(std::floor((p.y - y_min) / resolution));
  if (x < 0 || y < 0 || x >= size_x || y >= size_y || clearance.empty()) return 0;
  return std::max(0.0, clearance[static_cast<std::size_t>(y) * size_x + x] - resolution / 2);
}

double FreeSpace::pathDistanceAt(Vec2 p) const {
  const int x = static_cast<int>(std::floor((p.x - x_min) / resolution));
  const int y = static_cast<int>(std::floor((p.y - y_min) / resolution));
  if (x < 0 || y < 0 || x >= size_x || y >= size_y || path_distance.empty()) return 0;
  return std::max(0.0, path_distance[static_cast<std::size_t>(y) * size_x + x] - resolution);
}

double FreeSpace::freeRun(Vec2 from, double angle, double max) const {
  // Half-cell steps: a cell the line crosses only at a corner may be stepped over, which a
  // beam's own footprint (wider than a line) would not clear either way.
  const double step = resolution / 2, c = std::cos(angle), s = std::sin(angle);
  double d = 0;
  while (d < max && clearanceAt({from.x + d * c, from.y + d * s}) > 0) d += step;
  return std::min(d, max);
}

void limitBeamsWithoutReturn(ScanGeometry& scan, const FreeSpace& free) {
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    if (scan.valid[i] && scan.ranges[i] < scan.max_range) continue;
    const double angle = beamAngle(scan, static_cast<long>(i));
    scan.ranges[i] = static_cast<float>(free.freeRun(scan.sensor, angle, scan.max_range));
    scan.valid[i] = 0;
  }
}

std::vector<double> addedSlotTimes(double t_last, const AddObjectsSpec& spec) {
  const double begin = 0.15 * t_last, slot = 0.8 * t_last / spec.moves;
  std::vector<double> times;
  for (int k = 0; k < spec.moves; ++k) times.push_back(begin + k * slot);
  times.push_back(t_last);
  return times;
}

Vec2 addedPositionAt(const AddedPlan& plan, std::size_t index, double t) {
  const AddedObject& o = plan.objects.at(index);
  Vec2 p = o.start;
  for (const AddedMove& m : plan.moves) {
    if (m.object_id != o.id || m.t_start > t) continue;
    if (t >= m.t_end) {
      p = m.to;
    } else {
      const double f = (t - m.t_start) / (m.t_end - m.t_start);
      p = {m.from.x + f * (m.to.x - m.from.x), m.from.y + f * (m.to.y - m.from.y)};
    }
  }
  return p;
}

int beamsOnDisc(const ScanGeometry& scan, Vec2 centre, double radius, double counted_range) {
  const auto [lo, hi] = beamWindow(scan, centre, radius);
  int n = 0;
  for (long i = lo; i <= hi; ++i) {
    const double d = beamDistance(scan, i, centre, radius);
    n += d < scan.ranges[i] && d <= counted_range;
  }
  return n;
}

int ownReturnsInDisc(const ScanGeometry& scan, Vec2 centre, double radius) {
  const auto [lo, hi] = beamWindow(scan, centre, radius);
  int n = 0;
  for (long i = lo; i <= hi; ++i) {
    const float range = scan.ranges[static_cast<std::size_t>(i)];
    if (!scan.valid[static_cast<std::size_t>(i)] || !(range < scan.max_range)) continue;
    const double a = beamAngle(scan, i);
    const Vec2 end{scan.sensor.x + range * std::cos(a), scan.sensor.y + range * std::sin(a)};
    n += distance(end, centre) < radius;
  }
  return n;
}

std::size_t firstScanAt(const std::vector<ScanGeometry>& scans, double t) {
  return static_cast<std::size_t>(
      std::lower_bound(scans.begin(), scans.end(), t,
                       [](const ScanGeometry& s, double v) { return s.t < v; }) -
      scans.begin());
}

bool clearOfTheLog(const std::vector<ScanGeometry>& scans, Vec2 centre, double radius, double t0,
                   double t1) {
  for (std::size_t s = firstScanAt(scans, t0); s < scans.size() && scans[s].t <= t1; ++s) {
    if (ownReturnsInDisc(scans[s], centre, radius) > 0) return false;
  }
  return true;
}

std::vector<int> applyAddedObjects(const AddedPlan& plan, ScanGeometry& scan,
                                   const AddObjectsSpec& spec, std::uint64_t seed_stream) {
  std::vector<int> owner;
  std::vector<double> range;
  owners(plan, scan, owner, range);
  std::vector<int> hits(plan.objects.size(), 0);
  Rng rng(seed_stream);
  for (std::size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) continue;
    if (range[i] <= spec.counted_range_m) ++hits[static_cast<std::size_t>(owner[i])];
    const double noisy = std::max(0.01, range[i] + rng.gaussian(spec.range_noise_m));
    scan.ranges[i] = static_cast<float>(std::min<double>(noisy, scan.max_range));
    scan.valid[i] = 1;
  }
  return hits;
}

void dropUnseenMoves(const std::vector<ScanGeometry>& scans, const AddObjectsSpec& spec,
                     AddedPlan& plan) {
  for (bool dropped = true; dropped;) {
    dropped = false;
    // hits[scan][object] with every cylinder in.
    std::vector<std::vector<int>> hits(scans.size(), std::vector<int>(plan.objects.size(), 0));
    std::vector<int> owner;
    std::vector<double> range;
    for (std::size_t s = 0; s < scans.size(); ++s) {
      owners(plan, scans[s], owner, range);
      for (std::size_t i = 0; i < owner.size(); ++i) {
        if (owner[i] >= 0 && range[i] <= spec.counted_range_m) {
          ++hits[s][static_cast<std::size_t>(owner[i])];
        }
      }
    }
    for (std::size_t m = 0; m < plan.moves.size() && !dropped; ++m) {
      const AddedMove& mv = plan.moves[m];
      double next = std::numeric_limits<double>::infinity();
      for (std::size_t n = m + 1; n < plan.moves.size(); ++n) {
        if (plan.moves[n].object_id == mv.object_id) {
          next = plan.moves[n].t_start;
          break;
        }
      }
      const std::size_t k = objectIndexOf(plan, mv.object_id);
      const Sightings seen = sightings(scans, mv.t_end, next, spec.seen_beams,
                                       [&](std::size_t s) { return hits[s][k]; });
      if (seen.enough(spec)) continue;
      std::ostringstream why;
      why << "move of object " << mv.object_id << " at t " << mv.t_start << " s: its new place is "
          << "seen in " << seen.total << " scans before the object moves on (" << spec.seen_scans
          << " needed), " << seen.in_window << " of them in the detection window from the first ("
          << spec.window_seen << " needed), with the other cylinders in";
      dropMove(plan, m, why.str());
      dropped = true;
    }
  }
  renumberMoves(plan);
}

void dropMove(AddedPlan& plan, std::size_t m, const std::string& why) {
  plan.dropped.push_back(why);
  plan.moves.erase(plan.moves.begin() + static_cast<long>(m));
  // The moves after a dropped one start where the object now stands.
  for (AddedMove& mv : plan.moves) {
    mv.from = addedPositionAt(plan, objectIndexOf(plan, mv.object_id), mv.t_start - 1e-9);
  }
}

std::uint64_t addedNoiseStream(const AddObjectsSpec& spec, std::size_t index) {
  return spec.seed * 1000003ULL + index;
}

void dropMovesIntoHeldPlaces(const std::vector<ScanGeometry>& scans, const AddObjectsSpec& spec,
                             AddedPlan& plan, EditedMap& map) {
  std::size_t next = 0;  // the first move not yet asked about
  for (std::size_t s = 0; s < scans.size(); ++s) {
    while (next < plan.moves.size() && plan.moves[next].t_start <= scans[s].t) {
      const AddedMove& mv = plan.moves[next];
      const double radius = plan.objects[objectIndexOf(plan, mv.object_id)].diameter / 2;
      if (map.heldFree(mv.to, radius)) {
        ++next;
        continue;
      }
      std::ostringstream why;
      why << "move of object " << mv.object_id << " at t " << mv.t_start << " s: S of the "
          << "edited scans does not hold its new place free (occupied or unknown: a cylinder "
          << "stood there or in front of it, unseen since)";
      dropMove(plan, next, why.str());
    }
    ScanGeometry edited = scans[s];
    applyAddedObjects(plan, edited, spec, addedNoiseStream(spec, s));
    map.insert(s, edited);
  }
  renumberMoves(plan);
}

void renumberMoves(AddedPlan& plan) {
  for (std::size_t m = 0; m < plan.moves.size(); ++m) plan.moves[m].id = static_cast<int>(m) + 1;
}

}  // namespace dynamap::sim
