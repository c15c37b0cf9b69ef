// ObjectTracker::settleCarried: a continued session's carried ids given, at its end, to the
// present objects that fit them best (object_tracker.h).

#include <Eigen/Core>

#include <cmath>
#include <limits>

#include "dynamap/base/hungarian.h"
#include "dynamap/objects/object_tracker.h"

namespace dynamap {
namespace {

constexpr double kForbidden = std::numeric_limits<double>::infinity();

}  // namespace

std::map<int, int> ObjectTracker::carriedAssignment() const {
  // The holders an id may go to: the present objects (by id), and the places the tracker left
  // stale whose cells are still there, unseen empty (by minus their track's key): an id that
  // hopped to a detection elsewhere may belong where it was.
  std::vector<std::pair<int, const ShapeEstimate*>> holders;
  for (const TrackedObject& o : objects_) {
    if (o.state == ObjectState::Present) holders.push_back({o.id, &o.shape});
  }
  for (const auto& [key, tr] : tracks_) {
    if (const Stale* st = tr.stale(); st && !tr.cells.empty())
      holders.push_back({-key, &st->shape});
  }
  std::vector<int> carried;
  for (const TrackedObject& c : carried_) {
    if (listedInTable(c.state)) carried.push_back(c.id);
  }
  const auto n = static_cast<Eigen::Index>(holders.size());
  const auto m = static_cast<Eigen::Index>(carried.size());
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(n, m + n, kForbidden);
  // Between two sessions anything may have been carried anywhere: a distance says which of
  // two carried objects of a size it is, not whether it is one. Staying as it is costs more
  // than any pair allowed (size within size_tolerance, within far_match_distance).
  const double stay = 1.0 + options_.far_match_distance / options_.match_distance_scale;
  for (Eigen::Index i = 0; i < n; ++i) {
    const ShapeEstimate& s = *holders[static_cast<std::size_t>(i)].second;
    for (Eigen::Index j = 0; j < m; ++j) {
      const ShapeEstimate& c = carriedRow(carried[j]).shape;
      const double ds = std::abs(s.size - c.size);
      const double d = std::hypot(s.cx - c.cx, s.cy - c.cy);
      if (ds > options_.size_tolerance || d > options_.far_match_distance) continue;
      cost(i, j) = ds / options_.size_tolerance + d / options_.match_distance_scale;
    }
    cost(i, m + i) = stay;
  }
  const std::vector<int> pick = solveAssignment(cost, kForbidden);
  std::map<int, int> out;
  for (Eigen::Index i = 0; i < n; ++i) {
    const int j = pick[static_cast<std::size_t>(i)];
    const int now = holders[static_cast<std::size_t>(i)].first;
    const bool is_carried = now > 0 && isCarried(now);
    // Staying: a new object keeps its id, a carried id not kept takes a new one (0), a stale
    // place stays stale (its own entry).
    out[now] = j >= 0 && j < m ? carried[j] : (is_carried ? 0 : now);
  }
  return out;
}

void ObjectTracker::giveId(int to, const TrackedObject& row, bool fresh) {
  TrackedObject& o = object(to);
  const bool moved = !fresh && std::hypot(row.shape.cx - o.shape.cx, row.shape.cy - o.shape.cy) >
                                   options_.move_distance;
  // A fresh row was first seen when this session first found what it holds.
  if (fresh) o.first_seen_t = row.history.size() > 1 ? row.history[1].t : row.first_seen_t;
  o.shape = row.shape;
  o.state = ObjectState::Present;
  o.last_seen_t = row.last_seen_t;
  if (moved) ++o.n_moves;
  o.history.push_back({row.last_seen_t, row.shape.cx, row.shape.cy});
}

void ObjectTracker::settleCarried(double t, std::size_t scan_index) {
  if (carried_.empty()) return;
  // A carried id whose claim this session was withdrawn (a person standing, a report
  // retracted) was never this session's object: it is as it came.
  for (const TrackedObject& c : carried_) {
    if (listedInTable(c.state) && !listedInTable(object(c.id).state)) object(c.id) = c;
  }
  const std::map<int, int> target = carriedAssignment();
  std::map<int, TrackedObject> moving;  // holder now -> the row it brings, for those that change
  for (const auto& [now, to] : target) {
    if (now == to) continue;
    if (now > 0) {
      moving[now] = object(now);
      continue;
    }
    // A stale place taken again: the carried object there, of its carried size (the cells a
    // place keeps show less of the object than it showed whole).
    Track& tr = tracks_.at(-now);
    TrackedObject row = object(tr.stale()->object_id);
    const ShapeEstimate& place = tr.stale()->shape;
    row.shape = carriedRow(to).shape;
    row.shape.cx = place.cx;
    row.shape.cy = place.cy;
    row.history = {};
    tr.state = Confirmed{to, row.shape.cx, row.shape.cy, tr.stale()->best_cells, std::nullopt};
    moving[now] = row;
  }
  // First every row left behind: a carried one as it came (absent), a new one relabeled.
  for (const auto& kv : moving) {
    if (kv.first < 0) continue;
    TrackedObject& o = object(kv.first);
    if (isCarried(kv.first)) {
      o = carriedRow(kv.first);
    } else {
      o.state = ObjectState::Relabeled;
    }
  }
  std::map<int, int> renamed;  // id now -> id it holds from here on
  for (const auto& [now, row] : moving) {
    const bool fresh = target.at(now) == 0;
    const int to = fresh ? newObject(t) : target.at(now);
    giveId(to, row, fresh);
    emit(t, scan_index, object(to), ObjectEvent::Relabeled);
    events_.back().from_id = now > 0 ? now : row.id;
    if (now > 0) renamed[now] = to;
  }
  for (auto& kv : tracks_) {
    Track& tr = kv.second;
    if (Confirmed* c = tr.confirmed(); c && renamed.count(c->id)) c->id = renamed[c->id];
    if (Stale* st = tr.stale(); st && renamed.count(st->object_id)) {
      st->object_id = renamed[st->object_id];
    }
  }
}

bool ObjectTracker::retire(int id, double t, std::size_t scan_index) {
  if (id < 1 || id > static_cast<int>(objects_.size()) || !listedInTable(object(id).state)) {
    return false;
  }
  TrackedObject& o = object(id);
  if (isCarried(id)) {
    o = carriedRow(id);
    return true;
  }
  o.state = ObjectState::Retracted;
  emit(t, scan_index, o, ObjectEvent::Retracted);
  return true;
}

}  // namespace dynamap
