#include "dynamap/evaluation/evaluation.h"
// Table 3: objects and moves scored against the truth, and the ids set aside on real logs.
// Cells, trajectories and CLEAR MOT are scored in cell_scores.cpp, trajectory_error.cpp and
// clear_mot.cpp.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "by_scan.h"

namespace dynamap {
namespace {

BodyKey keyOf(const TruthRow& r) {
  return {r.kind, r.id};
}

std::vector<IdAssignment> assignIds(const ByScan& g, const EvalOptions& options) {
  std::map<int, std::map<BodyKey, std::size_t>> counts;
  std::map<int, IdAssignment> ids;
  for (const auto& [scan, rows] : g.tracks) {
    const auto& bodies = rowsAt(g.bodies, scan);
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
  forEachWindowScan(g, m, r, options,
                    [&](std::size_t scan, double t, const TruthRow& b,
                        const std::vector<const TruthRow*>& bodies) {
                      const auto tr = g.tracks.find(scan);
                      if (tr == g.tracks.end()) return;
                      std::set<int> ids_on_object;
                      for (const TrackRow* row : tr->second) {
                        if (!rowMatches(*row, b, options)) continue;
                        r.matched = true;
                        ids_on_object.insert(row->object_id);
                        const auto a = assigned.find(row->object_id);
                        if (a != assigned.end() && a->second == object) {
                          if (!r.correct) {
                            r.correct = true;
                            r.first_correct_scan = scan;
                            r.latency_s = t - r.visible_t;
                            r.latency_scans = scan - r.visible_scan;
                          }
                        } else {
                          r.wrong_id = true;
                        }
                        for (const TruthRow* other : bodies) {
                          if (other != &b && rowMatches(*row, *other, options))
                            r.double_match = true;
                        }
                      }
                      if (ids_on_object.size() > 1) r.double_match = true;
                    });
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

}  // namespace

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

bool inDetectWindow(const MoveResult& r, std::size_t scan, double t, const EvalOptions& options) {
  return scan >= r.visible_scan && (t <= r.visible_t + options.detect_window_s ||
                                    scan < r.visible_scan + options.detect_window_scans);
}

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

namespace {

// The places of the own rows, each with the first scan it was reported at: a grid of cells
// `radius` wide, each listing the distinct places (to 5 cm) in it.
struct OwnPlaces {
  struct Place {
    double x, y;
    std::size_t first_scan;
  };
  double radius;
  std::map<std::pair<long, long>, std::vector<Place>> cells;
  std::pair<long, long> cellOf(double x, double y) const {
    return {static_cast<long>(std::floor(x / radius)), static_cast<long>(std::floor(y / radius))};
  }
  OwnPlaces(const std::vector<OwnRow>& own, double r) : radius(r) {
    std::map<std::pair<long, long>, std::size_t> first;  // 5 cm place -> first scan
    for (const OwnRow& o : own) {
      const std::pair<long, long> k{std::lround(o.x / 0.05), std::lround(o.y / 0.05)};
      const auto it = first.find(k);
      if (it == first.end() || o.scan_index < it->second) first[k] = o.scan_index;
    }
    for (const auto& [k, scan] : first) {
      const double x = 0.05 * static_cast<double>(k.first),
                   y = 0.05 * static_cast<double>(k.second);
      cells[cellOf(x, y)].push_back({x, y, scan});
    }
  }
  // Whether (x, y) lies within radius of a place reported at or before `scan`.
  bool reportedBy(double x, double y, std::size_t scan) const {
    const auto [cx, cy] = cellOf(x, y);
    for (long dy = -1; dy <= 1; ++dy) {
      for (long dx = -1; dx <= 1; ++dx) {
        const auto it = cells.find({cx + dx, cy + dy});
        if (it == cells.end()) continue;
        for (const Place& p : it->second) {
          if (p.first_scan <= scan && std::hypot(x - p.x, y - p.y) <= radius) return true;
        }
      }
    }
    return false;
  }
};

}  // namespace

void setAsideLogOwn(ObjectScores& scores, const std::vector<TrackRow>& tracks,
                    const std::vector<OwnRow>& own, double radius) {
  const OwnPlaces places(own, radius);
  std::map<int, std::size_t> near_own;  // per tracker id, rows at a place of the log's own
  for (const TrackRow& r : tracks)
    near_own[r.object_id] += places.reportedBy(r.cx, r.cy, r.scan_index);
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