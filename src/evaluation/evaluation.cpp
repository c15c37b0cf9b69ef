#include "dynamap/evaluation/evaluation.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "dynamap/people/hungarian.h"

namespace dynamap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Cell borders computed as x_min + i·res carry rounding error; a wall lying exactly on a border
// must touch the cells on both sides of it, whatever that rounding did.
constexpr double kBorderEps = 1e-9;

double percent(std::size_t part, std::size_t whole) {
  return whole == 0 ? kNaN : 100.0 * static_cast<double>(part) / static_cast<double>(whole);
}

BodyKey keyOf(const TruthRow& r) {
  return {r.kind, r.id};
}

/// The truth and the tracks, grouped by scan.
struct ByScan {
  std::map<std::size_t, std::vector<const TruthRow*>> bodies;
  std::map<std::size_t, double> t;  // the truth's time of each scan
  std::map<std::size_t, std::vector<const TrackRow*>> tracks;
};

ByScan groupByScan(const std::vector<TruthRow>& rows, const std::vector<TrackRow>& tracks) {
  ByScan g;
  for (const auto& r : rows) {
    g.bodies[r.scan_index].push_back(&r);
    g.t[r.scan_index] = r.t;
  }
  const std::size_t last = g.t.empty() ? 0 : g.t.rbegin()->first;
  for (const auto& row : tracks) {
    if (g.t.empty() || row.scan_index > last) {
      throw std::invalid_argument("tracks: object " + std::to_string(row.object_id) + " at scan " +
                                  std::to_string(row.scan_index) +
                                  ", after the last scan of the truth (" + std::to_string(last) +
                                  "): tracks and truth are not from the same log");
    }
    g.tracks[row.scan_index].push_back(&row);
  }
  return g;
}

const TruthRow* findBody(const std::vector<const TruthRow*>& bodies, BodyKey key) {
  for (const TruthRow* b : bodies) {
    if (keyOf(*b) == key) return b;
  }
  return nullptr;
}

std::vector<IdAssignment> assignIds(const ByScan& g, const EvalOptions& options) {
  std::map<int, std::map<BodyKey, std::size_t>> counts;
  std::map<int, IdAssignment> ids;
  static const std::vector<const TruthRow*> kNone;
  for (const auto& [scan, rows] : g.tracks) {
    const auto it = g.bodies.find(scan);
    const auto& bodies = it == g.bodies.end() ? kNone : it->second;
    for (const TrackRow* row : rows) {
      IdAssignment& a = ids[row->object_id];
      a.track_id = row->object_id;
      ++a.rows;
      bool near = false;
      for (const TruthRow* b : bodies) {
        if (rowMatches(*row, *b, options)) ++counts[row->object_id][keyOf(*b)];
        if (distanceToBody(*row, *b) <= options.static_distance_m) near = true;
      }
      if (!near) ++a.far_rows;
    }
  }
  std::vector<IdAssignment> out;
  for (auto& [id, a] : ids) {
    for (const auto& [body, n] : counts[id]) {  // ascending keys: ties go to the first
      if (n > a.matches) {
        a.matches = n;
        a.body = body;
      }
    }
    a.static_object = 2 * a.far_rows > a.rows;
    out.push_back(a);
  }
  return out;
}

/// The scan the move becomes visible at: the first at or after t_end, before the object's next
/// move, where it stands at its new place and at least min_visible_hits beams end on it.
void findVisibility(const ByScan& g, const TruthMove& m, double next_start,
                    const EvalOptions& options, MoveResult& r) {
  for (const auto& [scan, bodies] : g.bodies) {
    const double t = g.t.at(scan);
    if (t < m.t_end) continue;
    if (t >= next_start) return;
    const TruthRow* b = findBody(bodies, {sim::BodyKind::Object, m.object_id});
    if (!b || sim::distance({b->x, b->y}, m.to) > options.place_tolerance_m) continue;
    if (b->hits < options.min_visible_hits) continue;
    r.visible = true;
    r.visible_scan = scan;
    r.visible_t = t;
    return;
  }
}

/// Looks at every scan of the detection window for rows matching the moved object.
void scoreWindow(const ByScan& g, const TruthMove& m, const std::map<int, BodyKey>& assigned,
                 const EvalOptions& options, MoveResult& r) {
  const BodyKey object{sim::BodyKind::Object, m.object_id};
  for (auto it = g.bodies.find(r.visible_scan); it != g.bodies.end(); ++it) {
    const double t = g.t.at(it->first);
    if (t > r.visible_t + options.detect_window_s &&
        it->first >= r.visible_scan + options.detect_window_scans) {
      break;
    }
    const TruthRow* b = findBody(it->second, object);
    if (!b || sim::distance({b->x, b->y}, m.to) > options.place_tolerance_m) continue;
    const auto tr = g.tracks.find(it->first);
    if (tr == g.tracks.end()) continue;
    std::set<int> ids_on_object;
    for (const TrackRow* row : tr->second) {
      if (!rowMatches(*row, *b, options)) continue;
      r.matched = true;
      ids_on_object.insert(row->object_id);
      const auto a = assigned.find(row->object_id);
      if (a != assigned.end() && a->second == object) {
        if (!r.correct) {
          r.correct = true;
          r.first_correct_scan = it->first;
          r.latency_s = t - r.visible_t;
          r.latency_scans = it->first - r.visible_scan;
        }
      } else {
        r.wrong_id = true;
      }
      for (const TruthRow* other : it->second) {
        if (other != b && rowMatches(*row, *other, options)) r.double_match = true;
      }
    }
    if (ids_on_object.size() > 1) r.double_match = true;
  }
}

/// The start of the next move of the same object after `m`, or +inf.
double nextStart(const std::vector<TruthMove>& moves, const TruthMove& m) {
  double next = std::numeric_limits<double>::infinity();
  for (const auto& o : moves) {
    if (o.object_id == m.object_id && o.t_start >= m.t_end && o.move_id != m.move_id) {
      next = std::min(next, o.t_start);
    }
  }
  return next;
}

LatencyStats latencyOf(const std::vector<MoveResult>& moves) {
  std::vector<double> s, n;
  for (const auto& m : moves) {
    if (!m.correct) continue;
    s.push_back(m.latency_s);
    n.push_back(static_cast<double>(m.latency_scans));
  }
  LatencyStats l;
  l.count = s.size();
  l.median_s = median(s);
  l.median_scans = median(n);
  l.max_s = s.empty() ? kNaN : *std::max_element(s.begin(), s.end());
  l.max_scans = n.empty() ? kNaN : *std::max_element(n.begin(), n.end());
  return l;
}

/// Cell index range [lo, hi] whose squares meet the closed interval [a, b] along one axis.
void cellRange(double a, double b, double origin, double res, int size, int& lo, int& hi) {
  lo = std::max(0, static_cast<int>(std::floor((a - origin) / res - kBorderEps)));
  hi = std::min(size - 1, static_cast<int>(std::floor((b - origin) / res + kBorderEps)));
}

/// Liang–Barsky: does segment s touch the closed box?
bool segmentTouchesBox(const sim::Segment& s, double x0, double y0, double x1, double y1) {
  double t0 = 0, t1 = 1;
  const double dx = s.b.x - s.a.x, dy = s.b.y - s.a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {s.a.x - x0, x1 - s.a.x, s.a.y - y0, y1 - s.a.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
    if (t0 > t1) return false;
  }
  return true;
}

bool occupiedNear(const CellMask& mask, const GridGeometry& g, int ix, int iy) {
  static const int kD[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& d : kD) {
    const int x = ix + d[0], y = iy + d[1];
    if (x >= 0 && y >= 0 && x < g.size_x && y < g.size_y && mask[g.index(x, y)]) return true;
  }
  return false;
}

}  // namespace

bool rowMatches(const TrackRow& row, const TruthRow& body, const EvalOptions& options) {
  const double radius = std::max(options.min_match_radius_m, body.diameter);
  return sim::distance({row.cx, row.cy}, {body.x, body.y}) <= radius;
}

double distanceToBody(const TrackRow& row, const TruthRow& body) {
  return std::max(0.0, sim::distance({row.cx, row.cy}, {body.x, body.y}) - body.diameter / 2);
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

ObjectScores evaluateObjects(const std::vector<TruthRow>& rows, const std::vector<TruthMove>& moves,
                             const std::vector<TrackRow>& tracks, const EvalOptions& options) {
  const ByScan g = groupByScan(rows, tracks);
  ObjectScores out;
  out.ids = assignIds(g, options);
  std::map<int, BodyKey> assigned;
  for (const auto& a : out.ids) {
    if (a.matches > 0) assigned[a.track_id] = a.body;
    if (a.static_object) ++out.static_as_objects;
    if (!a.static_object && a.matches > 0 && a.body.kind == sim::BodyKind::Person) {
      ++out.people_as_objects;
    }
  }
  std::vector<TruthMove> sorted = moves;
  std::sort(sorted.begin(), sorted.end(),
            [](const TruthMove& a, const TruthMove& b) { return a.move_id < b.move_id; });
  for (const auto& m : sorted) {
    MoveResult r;
    r.move_id = m.move_id;
    r.object_id = m.object_id;
    findVisibility(g, m, nextStart(sorted, m), options, r);
    if (r.visible) {
      scoreWindow(g, m, assigned, options, r);
      ++out.visible;
      out.correct += r.correct;
      out.not_detected += r.notDetected();
      out.size_errors += r.sizeError();
    }
    out.moves.push_back(r);
  }
  out.latency = latencyOf(out.moves);
  return out;
}

void rasteriseSegment(const sim::Segment& s, const GridGeometry& g, CellMask& mask) {
  int x_lo, x_hi, y_lo, y_hi;
  cellRange(std::min(s.a.x, s.b.x), std::max(s.a.x, s.b.x), g.x_min, g.resolution, g.size_x, x_lo,
            x_hi);
  cellRange(std::min(s.a.y, s.b.y), std::max(s.a.y, s.b.y), g.y_min, g.resolution, g.size_y, y_lo,
            y_hi);
  const double eps = kBorderEps * g.resolution;
  for (int iy = y_lo; iy <= y_hi; ++iy) {
    for (int ix = x_lo; ix <= x_hi; ++ix) {
      const double x0 = g.x_min + ix * g.resolution, y0 = g.y_min + iy * g.resolution;
      if (segmentTouchesBox(s, x0 - eps, y0 - eps, x0 + g.resolution + eps,
                            y0 + g.resolution + eps)) {
        mask[g.index(ix, iy)] = 1;
      }
    }
  }
}

void rasteriseWallGrid(const sim::WallGrid& walls, const GridGeometry& g, CellMask& mask) {
  const double r = walls.resolution;
  for (int py = 0; py < walls.height; ++py) {
    for (int px = 0; px < walls.width; ++px) {
      if (!walls.isWall(px, py)) continue;
      const double x0 = walls.origin.x + px * r, y0 = walls.origin.y + py * r;
      // Interiors overlap: shrink the pixel so a cell merely sharing its border is left out.
      int x_lo, x_hi, y_lo, y_hi;
      const double shrink = 1e-6 * std::min(r, g.resolution);
      cellRange(x0 + shrink, x0 + r - shrink, g.x_min, g.resolution, g.size_x, x_lo, x_hi);
      cellRange(y0 + shrink, y0 + r - shrink, g.y_min, g.resolution, g.size_y, y_lo, y_hi);
      for (int iy = y_lo; iy <= y_hi; ++iy) {
        for (int ix = x_lo; ix <= x_hi; ++ix) mask[g.index(ix, iy)] = 1;
      }
    }
  }
}

void rasteriseDisc(sim::Vec2 c, double radius, const GridGeometry& g, CellMask& mask) {
  int x_lo, x_hi, y_lo, y_hi;
  cellRange(c.x - radius, c.x + radius, g.x_min, g.resolution, g.size_x, x_lo, x_hi);
  cellRange(c.y - radius, c.y + radius, g.y_min, g.resolution, g.size_y, y_lo, y_hi);
  for (int iy = y_lo; iy <= y_hi; ++iy) {
    for (int ix = x_lo; ix <= x_hi; ++ix) {
      const double x0 = g.x_min + ix * g.resolution, y0 = g.y_min + iy * g.resolution;
      const double nx = std::clamp(c.x, x0, x0 + g.resolution);
      const double ny = std::clamp(c.y, y0, y0 + g.resolution);
      if (std::hypot(nx - c.x, ny - c.y) < radius) mask[g.index(ix, iy)] = 1;
    }
  }
}

CellTruth cellTruth(const sim::StaticWorld& world, const std::vector<TruthRow>& rows,
                    const std::vector<TruthMove>& moves, const GridGeometry& g) {
  CellTruth t;
  t.static_cells.assign(g.cells(), 0);
  for (const auto& s : world.segments) rasteriseSegment(s, g, t.static_cells);
  if (world.grid.width > 0) rasteriseWallGrid(world.grid, g, t.static_cells);

  std::map<int, double> first_move;  // object id -> start of its first move
  for (const auto& m : moves) {
    auto it = first_move.find(m.object_id);
    if (it == first_move.end() || m.t_start < it->second) first_move[m.object_id] = m.t_start;
  }
  t.dynamic_cells.assign(g.cells(), 0);
  t.world_at_end = t.static_cells;
  std::size_t last_scan = 0;
  for (const auto& r : rows) last_scan = std::max(last_scan, r.scan_index);
  for (const auto& r : rows) {
    const auto fm = first_move.find(r.id);
    const bool moving =
        r.kind == sim::BodyKind::Person || (fm != first_move.end() && r.t >= fm->second);
    if (moving) rasteriseDisc({r.x, r.y}, r.diameter / 2, g, t.dynamic_cells);
    if (r.scan_index == last_scan) rasteriseDisc({r.x, r.y}, r.diameter / 2, g, t.world_at_end);
  }
  for (std::size_t i = 0; i < g.cells(); ++i) {
    if (t.static_cells[i]) t.dynamic_cells[i] = 0;
  }
  return t;
}

CellScores scoreStaticMap(const std::vector<float>& s_occ, const CellTruth& truth,
                          const CellMask& observed, const GridGeometry& g) {
  CellMask occupied(g.cells(), 0);
  for (std::size_t i = 0; i < g.cells(); ++i) occupied[i] = s_occ[i] > 0.5f;
  CellScores c;
  for (int iy = 0; iy < g.size_y; ++iy) {
    for (int ix = 0; ix < g.size_x; ++ix) {
      const std::size_t i = g.index(ix, iy);
      if (!observed[i]) continue;
      if (truth.static_cells[i]) {
        ++c.static_cells;
        c.static_kept += occupiedNear(occupied, g, ix, iy);
      }
      if (truth.dynamic_cells[i]) {
        ++c.dynamic_cells;
        c.dynamic_clear += !occupied[i];
      }
    }
  }
  c.sa = percent(c.static_kept, c.static_cells);
  c.da = percent(c.dynamic_clear, c.dynamic_cells);
  c.aa = geometricMean(c.sa, c.da);
  c.ha = harmonicMean(c.sa, c.da);
  return c;
}

PrecisionRecall scoreOccupied(const CellMask& predicted, const CellMask& truth,
                              const CellMask& observed, const GridGeometry& g) {
  PrecisionRecall pr;
  for (int iy = 0; iy < g.size_y; ++iy) {
    for (int ix = 0; ix < g.size_x; ++ix) {
      const std::size_t i = g.index(ix, iy);
      if (!observed[i]) continue;
      if (predicted[i]) {
        ++pr.predicted;
        pr.predicted_right += occupiedNear(truth, g, ix, iy);
      }
      if (truth[i]) {
        ++pr.truth;
        pr.truth_found += occupiedNear(predicted, g, ix, iy);
      }
    }
  }
  pr.precision = percent(pr.predicted_right, pr.predicted);
  pr.recall = percent(pr.truth_found, pr.truth);
  return pr;
}

CellMask unionOccupied(const std::vector<float>& s_occ, const std::vector<float>& d_occ,
                       double object_threshold) {
  CellMask out(s_occ.size(), 0);
  for (std::size_t i = 0; i < s_occ.size(); ++i) {
    out[i] = s_occ[i] > 0.5f || d_occ[i] > object_threshold;
  }
  return out;
}

CellMask observedCells(const std::vector<const std::vector<float>*>& layers) {
  // MRPT's 8-bit cells move by at least 1/16 nat, i.e. ~0.016 in probability, from the prior.
  constexpr float kPriorTolerance = 1e-4f;
  CellMask out(layers.empty() ? 0 : layers.front()->size(), 0);
  for (const auto* layer : layers) {
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (std::abs((*layer)[i] - 0.5f) > kPriorTolerance) out[i] = 1;
    }
  }
  return out;
}

double geometricMean(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return kNaN;
  return std::sqrt(a * b);
}

double harmonicMean(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return kNaN;
  return a + b == 0 ? 0.0 : 2 * a * b / (a + b);
}

// --- trajectory level ------------------------------------------------------------------------

namespace {

double wrapAngle(double a) {
  return std::remainder(a, 2.0 * M_PI);
}

}  // namespace

const TimedPose* poseAtTime(const std::vector<TimedPose>& poses, double t, double tolerance) {
  auto it = std::lower_bound(poses.begin(), poses.end(), t - tolerance,
                             [](const TimedPose& p, double v) { return p.t < v; });
  const TimedPose* best = nullptr;
  for (; it != poses.end() && it->t <= t + tolerance; ++it) {
    if (!best || std::abs(it->t - t) < std::abs(best->t - t)) best = &*it;
  }
  return best;
}

TrajectoryError trajectoryError(const std::vector<TimedPose>& estimate,
                                const std::vector<TimedPose>& truth, double time_tolerance_s) {
  TrajectoryError e;
  bool anchored = false;
  double c = 1, s = 0, tx = 0, ty = 0, dphi = 0;  // estimate frame -> truth frame
  double sum_xy = 0, sum_phi = 0;
  for (const TimedPose& p : estimate) {
    const TimedPose* g = poseAtTime(truth, p.t, time_tolerance_s);
    if (!g) {
      ++e.unmatched;
      continue;
    }
    if (!anchored) {  // the rotation and translation that put this pose on the truth's
      dphi = wrapAngle(g->phi - p.phi);
      c = std::cos(dphi), s = std::sin(dphi);
      tx = g->x - (c * p.x - s * p.y);
      ty = g->y - (s * p.x + c * p.y);
      anchored = true;
    }
    const double x = c * p.x - s * p.y + tx, y = s * p.x + c * p.y + ty;
    const double d2 = (x - g->x) * (x - g->x) + (y - g->y) * (y - g->y);
    const double dp = wrapAngle(p.phi + dphi - g->phi);
    sum_xy += d2;
    sum_phi += dp * dp;
    e.max_xy_m = std::max(e.max_xy_m, std::sqrt(d2));
    ++e.matched;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  e.rmse_xy_m = e.matched ? std::sqrt(sum_xy / static_cast<double>(e.matched)) : nan;
  e.rmse_phi_rad = e.matched ? std::sqrt(sum_phi / static_cast<double>(e.matched)) : nan;
  if (!e.matched) e.max_xy_m = nan;
  return e;
}

// --- people (CLEAR MOT) --------------------------------------------------------------------------

namespace {

struct MotFrame {
  std::vector<const TruthRow*> people;
  std::vector<const PersonTrackRow*> tracks;
};

// The track each person of the frame is matched to (-1: none): last scan's pairs first.
std::vector<int> matchFrame(const MotFrame& f, const std::map<int, int>& last, double gate) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<int> match(f.people.size(), -1);
  std::vector<char> taken(f.tracks.size(), 0);
  auto dist = [&](std::size_t i, std::size_t j) {
    return std::hypot(f.people[i]->x - f.tracks[j]->x, f.people[i]->y - f.tracks[j]->y);
  };
  for (std::size_t i = 0; i < f.people.size(); ++i) {
    const auto it = last.find(f.people[i]->id);
    if (it == last.end()) continue;
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      if (!taken[j] && f.tracks[j]->person_id == it->second && dist(i, j) <= gate) {
        match[i] = static_cast<int>(j);
        taken[j] = 1;
      }
    }
  }
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(f.people.size()),
                       static_cast<Eigen::Index>(f.tracks.size()));
  for (std::size_t i = 0; i < f.people.size(); ++i) {
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      const bool open = match[i] < 0 && !taken[j] && dist(i, j) <= gate;
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = open ? dist(i, j) : inf;
    }
  }
  const std::vector<int> rest = solveAssignment(cost, inf);
  for (std::size_t i = 0; i < f.people.size(); ++i) {
    if (match[i] < 0) match[i] = rest[i];
  }
  return match;
}

/// When each person of the truth stood still: [first, last] time of each stop (MotOptions).
std::map<int, std::vector<std::pair<double, double>>> personStops(
    const std::vector<TruthRow>& truth, const MotOptions& o) {
  std::map<int, std::vector<const TruthRow*>> rows;
  for (const TruthRow& r : truth) {
    if (r.kind == sim::BodyKind::Person) rows[r.id].push_back(&r);
  }
  std::map<int, std::vector<std::pair<double, double>>> stops;
  for (auto& [id, v] : rows) {
    std::stable_sort(v.begin(), v.end(), [](const TruthRow* a, const TruthRow* b) {
      return a->scan_index < b->scan_index;
    });
    std::size_t first = 0;  // the run of rows within stop_radius_m of v[first]
    for (std::size_t i = 1; i <= v.size(); ++i) {
      if (i < v.size() &&
          std::hypot(v[i]->x - v[first]->x, v[i]->y - v[first]->y) <= o.stop_radius_m) {
        continue;
      }
      if (v[i - 1]->t - v[first]->t >= o.stop_min_s) stops[id].emplace_back(v[first]->t, v[i - 1]->t);
      first = i;
    }
  }
  return stops;
}

bool atStop(const std::vector<std::pair<double, double>>& stops, double t, const MotOptions& o) {
  return std::any_of(stops.begin(), stops.end(), [&](const std::pair<double, double>& s) {
    return t >= s.first && t <= s.second + o.after_stop_s;
  });
}

}  // namespace

MotScores evaluateClearMot(const std::vector<TruthRow>& truth,
                           const std::vector<PersonTrackRow>& tracks, const MotOptions& o) {
  std::map<std::size_t, MotFrame> frames;
  for (const TruthRow& r : truth) {
    if (r.kind == sim::BodyKind::Person) frames[r.scan_index].people.push_back(&r);
  }
  for (const PersonTrackRow& r : tracks) {
    auto it = frames.find(r.scan_index);
    if (it != frames.end()) it->second.tracks.push_back(&r);
  }
  MotScores s;
  const auto stops = personStops(truth, o);
  std::map<int, int> last;  // person -> the track it was last matched to
  std::set<int> people, ids;
  double sum = 0;
  for (const auto& [scan, f] : frames) {
    const std::vector<int> match = matchFrame(f, last, o.gate_m);
    std::vector<char> used(f.tracks.size(), 0);
    for (std::size_t i = 0; i < f.people.size(); ++i) {
      const TruthRow& p = *f.people[i];
      if (match[i] >= 0) used[static_cast<std::size_t>(match[i])] = 1;
      if (p.hits < o.min_visible_hits) continue;  // not counted either way
      ++s.ground_truth;
      people.insert(p.id);
      if (match[i] < 0) {
        ++s.misses;
        continue;
      }
      const PersonTrackRow& t = *f.tracks[static_cast<std::size_t>(match[i])];
      ++s.matches;
      sum += std::hypot(p.x - t.x, p.y - t.y);
      const auto it = last.find(p.id);
      if (it != last.end() && it->second != t.person_id) {
        ++s.id_switches;
        const auto st = stops.find(p.id);
        const bool at_stop = st != stops.end() && atStop(st->second, p.t, o);
        s.id_switches_at_stops += at_stop;
        s.switches.push_back({scan, p.t, p.id, it->second, t.person_id, at_stop});
      }
      last[p.id] = t.person_id;
    }
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      ids.insert(f.tracks[j]->person_id);
      if (!used[j]) ++s.false_positives;
    }
  }
  s.people = people.size();
  s.track_ids = ids.size();
  s.motp_m = s.matches ? sum / static_cast<double>(s.matches) : std::nan("");
  s.mota = s.ground_truth ? 1.0 - static_cast<double>(s.misses + s.false_positives + s.id_switches) /
                                      static_cast<double>(s.ground_truth)
                          : std::nan("");
  return s;
}

namespace {

/// The closed-form rotation and translation putting `est`'s positions onto `gt`'s (least
/// squares), and the RMSE after it.
double alignedRmse(const std::vector<TimedPose>& est, const std::vector<TimedPose>& gt) {
  const double n = static_cast<double>(est.size());
  double ex = 0, ey = 0, gx = 0, gy = 0;
  for (std::size_t i = 0; i < est.size(); ++i)
    ex += est[i].x, ey += est[i].y, gx += gt[i].x, gy += gt[i].y;
  ex /= n, ey /= n, gx /= n, gy /= n;
  double sxx = 0, sxy = 0;  // sum of dot and cross products of the centred positions
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double ax = est[i].x - ex, ay = est[i].y - ey, bx = gt[i].x - gx, by = gt[i].y - gy;
    sxx += ax * bx + ay * by;
    sxy += ax * by - ay * bx;
  }
  const double th = std::atan2(sxy, sxx), c = std::cos(th), s = std::sin(th);
  double sum = 0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double ax = est[i].x - ex, ay = est[i].y - ey;
    const double dx = c * ax - s * ay + gx - gt[i].x, dy = s * ax + c * ay + gy - gt[i].y;
    sum += dx * dx + dy * dy;
  }
  return std::sqrt(sum / n);
}

/// The motion from a to b in a's frame.
TimedPose relative(const TimedPose& a, const TimedPose& b) {
  const double c = std::cos(a.phi), s = std::sin(a.phi), dx = b.x - a.x, dy = b.y - a.y;
  return {0, c * dx + s * dy, -s * dx + c * dy, wrapAngle(b.phi - a.phi)};
}

/// Mean relative error over pairs `delta` metres of the truth's path apart (each pose i with
/// the first j whose path from i reaches delta).
void relativeError(const std::vector<TimedPose>& est, const std::vector<TimedPose>& gt,
                   double delta, double& xy, double& phi) {
  std::vector<double> path(gt.size(), 0.0);
  for (std::size_t i = 1; i < gt.size(); ++i) {
    path[i] = path[i - 1] + std::hypot(gt[i].x - gt[i - 1].x, gt[i].y - gt[i - 1].y);
  }
  double sum_xy = 0, sum_phi = 0;
  std::size_t pairs = 0, j = 0;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    j = std::max(j, i);
    while (j < gt.size() && path[j] - path[i] < delta) ++j;
    if (j >= gt.size()) break;
    const TimedPose e = relative(est[i], est[j]), g = relative(gt[i], gt[j]);
    sum_xy += std::hypot(e.x - g.x, e.y - g.y);
    sum_phi += std::abs(wrapAngle(e.phi - g.phi));
    ++pairs;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  xy = pairs ? sum_xy / static_cast<double>(pairs) : nan;
  phi = pairs ? sum_phi / static_cast<double>(pairs) : nan;
}

}  // namespace

AlignedTrajectoryError alignedTrajectoryError(const std::vector<TimedPose>& estimate,
                                              const std::vector<TimedPose>& truth,
                                              double time_tolerance_s) {
  std::vector<TimedPose> est, gt;
  for (const TimedPose& p : estimate) {
    const TimedPose* g = poseAtTime(truth, p.t, time_tolerance_s);
    if (!g) continue;
    est.push_back(p);
    gt.push_back(*g);
  }
  AlignedTrajectoryError e;
  e.matched = est.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  e.aligned_rmse_xy_m = est.empty() ? nan : alignedRmse(est, gt);
  relativeError(est, gt, 1.0, e.rel_1m_xy_m, e.rel_1m_phi_rad);
  relativeError(est, gt, 10.0, e.rel_10m_xy_m, e.rel_10m_phi_rad);
  return e;
}

void setAsideLogOwn(ObjectScores& scores, const std::vector<TrackRow>& tracks,
                    const std::vector<OwnRow>& own, double radius) {
  std::map<std::size_t, std::vector<const OwnRow*>> by_scan;
  for (const OwnRow& o : own) by_scan[o.scan_index].push_back(&o);
  std::map<int, std::size_t> near_own;  // per tracker id, rows near an own row
  for (const TrackRow& r : tracks) {
    const auto it = by_scan.find(r.scan_index);
    if (it == by_scan.end()) continue;
    for (const OwnRow* o : it->second) {
      if (std::hypot(r.cx - o->x, r.cy - o->y) <= radius) {
        ++near_own[r.object_id];
        break;
      }
    }
  }
  for (IdAssignment& a : scores.ids) {
    if (!a.static_object || 2 * near_own[a.track_id] <= a.rows) continue;
    a.static_object = false;
    a.log_own = true;
    --scores.static_as_objects;
    ++scores.log_own_objects;
  }
}

void setAsideLeftBehind(ObjectScores& scores, const std::vector<TrackRow>& tracks,
                        const std::vector<TruthRow>& rows, const EvalOptions& options) {
  struct Place {
    double x, y, radius;
    std::size_t first_scan;
  };
  std::vector<Place> places;
  std::map<int, const TruthRow*> last;  // per object, its row at its latest place
  for (const TruthRow& r : rows) {
    if (r.kind != sim::BodyKind::Object) continue;
    const TruthRow*& l = last[r.id];
    if (l != nullptr && std::hypot(r.x - l->x, r.y - l->y) <= options.place_tolerance_m) continue;
    l = &r;
    places.push_back({r.x, r.y, std::max(options.min_match_radius_m, r.diameter), r.scan_index});
  }
  std::map<int, std::size_t> near_place;  // per tracker id, rows where an object had stood
  for (const TrackRow& t : tracks) {
    for (const Place& p : places) {
      if (p.first_scan <= t.scan_index && std::hypot(t.cx - p.x, t.cy - p.y) <= p.radius) {
        ++near_place[t.object_id];
        break;
      }
    }
  }
  for (IdAssignment& a : scores.ids) {
    if (!a.static_object || 2 * near_place[a.track_id] <= a.rows) continue;
    a.static_object = false;
    a.left_behind = true;
    --scores.static_as_objects;
    ++scores.left_behind_objects;
  }
}

}  // namespace dynamap
