#include "dynamap/objects/object_tracker.h"
// The object tracker's second half: tracks confirmed as objects, their identities, reviews and
// moves, and the object table. D's cells become tracks in object_tracker_cells.cpp.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {

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
  map_ = &map;  // for the walls viewOfShape asks about, during this update
  collectPoints(map, view);
  measureOutlines(view);
  // 3. Objects whose cells all faded were seen gone: disappeared.
  dropLostTracks(t, scan_index);
  // 4. Places left by unseen moves: seen free ends them, seen occupied revives them.
  checkStalePlaces(view, t, scan_index);
  // 5. Reported clusters whose size has settled: their identity is judged again.
  reviewReports(view, t, scan_index);
  // 6. Clusters that lasted report_scans get an identity by size: new, moved, reappeared.
  confirmTentatives(view, t, scan_index);
  // 7. Present objects that drifted (a person walking) moved; refresh the table.
  checkDrift(t, scan_index);
  updateLastSeen(view, t);
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
    if (const Confirmed* c = tr.confirmed(); c && c->review) {
      // Seen empty before its size settled: the report is withdrawn.
      emit(t, scan_index, object(c->id), ObjectEvent::Retracted);
      undoClaim(key, ObjectState::Retracted, t, scan_index);
    } else if (c) {
      TrackedObject& o = object(c->id);
      // Gone soon after it first came, from a place it had never left: it only paused there.
      const bool brief =
          o.n_moves == 0 && o.history.size() <= 1 && t - o.first_seen_t < options_.min_rest_s;
      o.state = brief ? ObjectState::Retracted : ObjectState::Absent;
      o.vanished_t = t;
      emit(t, scan_index, o, brief ? ObjectEvent::Retracted : ObjectEvent::Disappeared);
    }
    pending_.erase(key);
    reviewing_.erase(key);
    tracks_.erase(it);
  }
}

void ObjectTracker::checkStalePlaces(const ScanView& view, double t, std::size_t scan_index) {
  for (auto& kv : tracks_) {
    Track& tr = kv.second;
    Stale* st = tr.stale();
    if (!st) continue;
    const PlaceView pv = viewOfShape(view, st->shape);
    st->seen_occupied = pv == PlaceView::SeenOccupied ? st->seen_occupied + 1 : 0;
    // Seen occupied longer than D needs to fade a vacated cell: the object never left.
    if (st->seen_occupied <= options_.confirm_scans + 4) continue;
    const auto took = tracks_.find(st->moved_to);
    if (took != tracks_.end() && took->second.objectId() == st->object_id) {
      revive(tr, st->moved_to, view, t, scan_index);
      continue;
    }
    // Its object has moved on since: what is here is a new object, and never that one.
    Tentative reopened;
    reopened.exclude_id = st->object_id;
    tr.state = reopened;
    pending_.insert(kv.first);
  }
}

void ObjectTracker::revive(Track& place, int took, const ScanView& view, double t,
                           std::size_t scan_index) {
  const Stale st = *place.stale();
  const int id = st.object_id;
  Confirmed& c = *tracks_[took].confirmed();
  const ShapeEstimate s = object(id).shape;  // the detection's: its row followed the track
  std::optional<Review> review = std::move(c.review);
  c.review.reset();
  TrackedObject& o = object(id);
  o.n_moves = std::max(0, o.n_moves - 1);  // the move was not one
  o.shape = st.shape;
  o.state = ObjectState::Present;
  o.last_seen_t = t;
  o.history.push_back({t, o.shape.cx, o.shape.cy});
  place.state = Confirmed{id, st.shape.cx, st.shape.cy, st.best_cells, std::nullopt};
  emit(t, scan_index, o, ObjectEvent::Reappeared);
  // The detection is another object: the one that fits now (one seen gone since, say), or new.
  const int other = pickIdentity(s, id, -1, view, t);
  if (review) review->claimed = false;
  claim(took, other, s, std::move(review), t, scan_index);
}

void ObjectTracker::confirmTentatives(const ScanView& view, double t, std::size_t scan_index) {
  std::set<int> candidates = pending_;
  for (const int key : touched_) candidates.insert(key);
  for (const int key : candidates) {
    auto it = tracks_.find(key);
    Tentative* tent = it == tracks_.end() ? nullptr : it->second.tentative();
    if (!tent) {
      pending_.erase(key);
      continue;
    }
    const Track& tr = it->second;
    const int support = supportCells(*map_, tr);
    if (!passesFilters(tr, tent->shape, options_, support)) {
      tent->restart();
      // Short of cells alone, it is judged again each scan: its neighbours may gather hits.
      if (!shortOfCells(tr)) pending_.erase(key);
      continue;
    }
    if (partOfASeenObject(tent->shape, view)) {
      tent->restart();
      continue;
    }
    if (!tent->kept_out && tent->run.passes > 0) tent->settling_before_people = true;
    if (!tent->settling_before_people && nearKeepOut(tent->shape)) {
      // A person there now: judged again once they have left.
      tent->restart();
      tent->kept_out = true;
      pending_.insert(key);
      continue;
    }
    pending_.insert(key);
    if (tent->kept_out && viewOfShape(view, tent->shape) != PlaceView::SeenOccupied) continue;
    if (tent->run.passes == 0) tent->first_t = t;
    // Count only scans that left its size as it was: an object is judged once its size has
    // settled (it is all there, and the robot has seen enough of it to tell its size).
    tent->run.pass(tent->shape.size, options_.settle_size);
    // Short of cells alone (support), its outlines are of an arc seen in part: a provisional
    // identity waits for a cluster of its own cells.
    if (const auto o = outline_now_.find(key); o != outline_now_.end() && support == 0) {
      tent->outline.add(o->second.first, o->second.second);
    }
    if (tent->run.passes < options_.confirm_scans && tent->outline.count < options_.report_scans) {
      continue;
    }
    if (confirm(key, view, t, scan_index)) {
      pending_.erase(key);
    }
  }
}

void ObjectTracker::carryOver(std::vector<TrackedObject> rows, double t) {
  if (!objects_.empty() || !tracks_.empty() || !events_.empty()) {
    throw std::logic_error("ObjectTracker::carryOver: the table is no longer empty");
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    TrackedObject& o = rows[k];
    if (o.id != static_cast<int>(k) + 1) {
      throw std::logic_error("ObjectTracker::carryOver: ids must be 1, 2, ... in order");
    }
    o.label = "object" + std::to_string(o.id);
    o.history = {{o.last_seen_t, o.shape.cx, o.shape.cy}};
    if (listedInTable(o.state)) {
      o.state = ObjectState::Absent;
      o.vanished_t = t;
    }
  }
  carried_ = rows;
  objects_ = std::move(rows);
}

int ObjectTracker::newObject(double t) {
  TrackedObject o;
  o.id = static_cast<int>(objects_.size()) + 1;
  o.label = "object" + std::to_string(o.id);
  o.first_seen_t = t;
  objects_.push_back(o);
  return o.id;
}

void ObjectTracker::identityCandidates(const ShapeEstimate& s, int exclude_id, const ScanView& view,
                                       double t, std::vector<IdentityCandidate>& cands,
                                       std::vector<int>& ids) const {
  for (const TrackedObject& o : objects_) {
    if (o.id == exclude_id || !listedInTable(o.state) || underReview(o.id)) continue;
    const bool absent = o.state == ObjectState::Absent;
    const double dist = std::hypot(o.shape.cx - s.cx, o.shape.cy - s.cy);
    // A present object right here would have been followed, not re-found.
    if (!absent && dist <= options_.reappear_distance) continue;
    PlaceView pv = PlaceView::NotInView;
    if (!absent) pv = viewOfShape(view, o.shape);
    // Seen in place a moment ago and not seen gone since: it did not cross the room unseen.
    if (!absent && pv != PlaceView::SeenFree && t - o.last_seen_t < options_.min_unseen_s) {
      continue;
    }
    cands.push_back({o.shape.cx, o.shape.cy, o.shape.size, absent, o.vanished_t, pv});
    ids.push_back(o.id);
  }
  // A far candidate needs the size nearest the detection's among all known objects, candidates
  // or not (an object seen in place shares a size as much as one that could have moved).
  for (std::size_t k = 0; k < cands.size(); ++k) {
    const double own = std::abs(cands[k].size - s.size) + options_.far_size_margin;
    for (const TrackedObject& o : objects_) {
      if (o.id == ids[k] || o.id == exclude_id || !listedInTable(o.state)) continue;
      if (std::abs(o.shape.size - s.size) < own) cands[k].shared_size = true;
    }
  }
}

int ObjectTracker::pickIdentity(const ShapeEstimate& s, int exclude_id, double slack,
                                const ScanView& view, double t) const {
  std::vector<IdentityCandidate> cands;
  std::vector<int> ids;
  identityCandidates(s, exclude_id, view, t, cands, ids);
  const int pick = chooseIdentity(s, t, cands, options_);
  if (slack > 0) {
    // The choice must hold for any size within `slack` of this one. Each candidate's cost is
    // linear in the size on either side of its own, so the pairwise order changes
    // monotonically with it: the pick at both ends and at the middle is the pick throughout.
    for (const double sign : {-1.0, 1.0}) {
      ShapeEstimate end = s;
      end.size += sign * slack;
      if (chooseIdentity(end, t, cands, options_) != pick) return -1;
    }
  }
  return pick < 0 ? 0 : ids[static_cast<std::size_t>(pick)];
}

bool ObjectTracker::confirm(int key, const ScanView& view, double t, std::size_t scan_index) {
  const Tentative tent = *tracks_[key].tentative();
  const bool final = tent.run.passes >= options_.confirm_scans;
  // Before confirm_scans, only a scan that shows the object whole tells its size well enough,
  // and then only a choice that its error could not change.
  ShapeEstimate s = tent.shape;
  double error = -1;
  if (!final) {  // the size its outline shows
    s.size = tent.outline.size();
    error = tent.outline.error();
  }
  int id = pickIdentity(s, tent.exclude_id, error * options_.report_errors, view, t);
  if (id < 0) return false;
  // Only an object still shown at a place out of sight fits: wait until that place is seen
  // (free: it moved here; occupied: this is another object), for at most defer_s.
  if (id && object(id).state == ObjectState::Present && t - tent.first_t < options_.defer_s) {
    if (final) return false;
    id = 0;  // reported as new meanwhile; the review decides
  }
  std::optional<Review> review;
  if (!final) {
    review = Review{tent.run, tent.first_t, tent.exclude_id, false, {}};
    reviewing_.insert(key);
  }
  claim(key, id, s, std::move(review), t, scan_index);
  return true;
}

void ObjectTracker::claim(int key, int id, const ShapeEstimate& s, std::optional<Review> review,
                          double t, std::size_t scan_index) {
  ObjectEvent ev = ObjectEvent::New;
  if (!id) {
    id = newObject(t);
  } else {
    TrackedObject& o = object(id);
    if (review) review->claimed = true, review->before = o;
    const bool present = o.state == ObjectState::Present;
    // Its old place was not seen vacated: keep those cells as a stale place to check.
    if (present) leavePlace(id, key);
    const double dist = std::hypot(o.shape.cx - s.cx, o.shape.cy - s.cy);
    const bool back = !present && dist <= options_.reappear_distance;
    ev = back ? ObjectEvent::Reappeared : ObjectEvent::Moved;
    if (ev == ObjectEvent::Moved) ++o.n_moves;
  }
  tracks_[key].state = Confirmed{id, s.cx, s.cy, s.cells, std::move(review)};
  TrackedObject& o = object(id);
  o.shape = s;
  o.state = ObjectState::Present;
  o.last_seen_t = t;
  o.history.push_back({t, o.shape.cx, o.shape.cy});
  emit(t, scan_index, o, ev);
}

void ObjectTracker::reviewReports(const ScanView& view, double t, std::size_t scan_index) {
  const std::vector<int> keys(reviewing_.begin(), reviewing_.end());
  for (const int key : keys) {
    const auto it = tracks_.find(key);
    Confirmed* c = it == tracks_.end() ? nullptr : it->second.confirmed();
    if (!c || !c->review) {
      reviewing_.erase(key);
      continue;
    }
    Review& r = *c->review;
    const ShapeEstimate& s = object(c->id).shape;
    if (!passesFilters(it->second, s, options_) || nearKeepOut(s)) {
      r.run.passes = 0;
      continue;
    }
    r.run.pass(s.size, options_.settle_size);
    if (r.run.passes >= options_.confirm_scans) settle(key, view, t, scan_index);
  }
}

void ObjectTracker::settle(int key, const ScanView& view, double t, std::size_t scan_index) {
  Confirmed& c = *tracks_[key].confirmed();
  const Review r = *c.review;
  const int current = c.id;
  const ShapeEstimate s = object(current).shape;
  // The table as it would be without this report: the claimed object's row as it was, or no
  // row for a new one.
  const TrackedObject now = object(current);
  if (r.claimed) {
    object(current) = r.before;
  } else {
    object(current).state = ObjectState::Relabeled;
  }
  reviewing_.erase(key);  // its own claim is no obstacle
  const int id = pickIdentity(s, r.exclude_id, -1, view, t);
  object(current) = now;
  // No other known object fits, but the claimed one's size still does (a far one, say, whose
  // size another object's comes close to) and its old place is not seen occupied: nothing
  // contradicts the report.
  const bool still_fits = r.claimed && id == 0 &&
                          std::abs(s.size - r.before.shape.size) <= options_.size_tolerance &&
                          !leftPlaceSeenOccupied(current, key);
  if (still_fits || id == (r.claimed ? current : 0)) {
    c.review.reset();  // the identity stands
    return;
  }
  // Another object still shown at a place out of sight: wait for that place, up to defer_s.
  if (id && object(id).state == ObjectState::Present && t - r.first_t < options_.defer_s) {
    reviewing_.insert(key);
    return;
  }
  undoClaim(key, ObjectState::Relabeled, t, scan_index);
  claim(key, id, s, std::nullopt, t, scan_index);
  EventRecord e = events_.back();
  e.event = ObjectEvent::Relabeled;
  e.from_id = current;
  events_.push_back(e);
}

void ObjectTracker::undoClaim(int key, ObjectState hidden, double t, std::size_t scan_index) {
  Confirmed& c = *tracks_[key].confirmed();
  const Review r = *c.review;
  TrackedObject& o = object(c.id);
  c.review.reset();
  if (!r.claimed) {
    o.state = hidden;
    return;
  }
  o = r.before;
  if (o.state != ObjectState::Present) return;
  // The place it left for this report is its place again, unless that was seen empty since.
  for (auto& kv : tracks_) {
    const Stale* st = kv.second.stale();
    if (!st || st->object_id != o.id || st->moved_to != key) continue;
    o.shape = st->shape;
    kv.second.state = Confirmed{o.id, st->shape.cx, st->shape.cy, st->best_cells, std::nullopt};
    return;
  }
  o.state = ObjectState::Absent;
  o.vanished_t = t;
  emit(t, scan_index, o, ObjectEvent::Disappeared);
}

bool ObjectTracker::measureOutline(const ScanView& view, int key, const ShapeEstimate& s,
                                   double& size, double& gap) const {
  const auto b = beam_on_.find(key);
  if (b == beam_on_.end()) return false;
  const BeamRun run = beamRunAround(view, b->second, options_.outline_jump);
  if (!run.whole()) return false;
  std::vector<double> xs, ys;
  for (std::size_t i = run.first; i <= run.last; ++i) {
    xs.push_back(0);
    ys.push_back(0);
    hitPoint(view, i, xs.back(), ys.back());
  }
  gap = view.ranges[b->second] * std::abs(view.step);
  ShapeEstimate outline;
  ObjectOptions few = options_;  // an outline of a small object has few points
  few.min_fit_cells = 3;
  // Fewer than three beams (the fit's minimum) measure no size and place one can trust.
  if (!estimatePointShape(xs, ys, gap, view.x, view.y, few, outline)) return false;
  size = outline.size;
  // The outline is this object's: no larger than an object, and holding its cells.
  const double off = std::hypot(outline.cx - s.cx, outline.cy - s.cy);
  return size <= options_.max_size && s.size <= size + gap && off <= 0.5 * size + resolution_;
}

bool ObjectTracker::leftPlaceSeenOccupied(int id, int key) const {
  for (const auto& kv : tracks_) {
    const Stale* st = kv.second.stale();
    if (st && st->object_id == id && st->moved_to == key && st->seen_occupied > 0) return true;
  }
  return false;
}

void ObjectTracker::measureOutlines(const ScanView& view) {
  outline_now_.clear();
  for (const auto& kb : beam_on_) {
    Track& tr = tracks_[kb.first];
    double size = 0, gap = 0;
    if (tr.isStale() || !measureOutline(view, kb.first, shapeOf(tr), size, gap)) continue;
    outline_now_[kb.first] = {size, gap};
    tr.outline.add(size, gap);
    refresh(tr, resolution_);
    touched_.insert(kb.first);  // its size may now pass the filters
  }
}

bool ObjectTracker::underReview(int id) const {
  for (const int key : reviewing_) {
    const auto it = tracks_.find(key);
    if (it != tracks_.end() && it->second.objectId() == id) return true;
  }
  return false;
}

void ObjectTracker::leavePlace(int id, int moved_to) {
  const int old = trackOf(id);
  if (!old) return;
  Track& place = tracks_[old];
  Stale st;
  st.object_id = id;
  st.moved_to = moved_to;
  st.shape = object(id).shape;  // the place it left; its row takes where it went
  st.best_cells = place.confirmed()->best_cells;
  place.state = st;
}

void ObjectTracker::checkDrift(double t, std::size_t scan_index) {
  for (const int key : touched_) {
    auto it = tracks_.find(key);
    if (it == tracks_.end()) continue;
    Track& tr = it->second;
    Confirmed* c = tr.confirmed();
    if (!c || tr.cells.empty()) continue;
    TrackedObject& o = object(c->id);
    if (c->review) {  // still being measured: its centre moves as more of it is seen
      c->anchor_x = o.shape.cx;
      c->anchor_y = o.shape.cy;
      continue;
    }
    if (std::hypot(o.shape.cx - c->anchor_x, o.shape.cy - c->anchor_y) > options_.move_distance) {
      c->anchor_x = o.shape.cx;
      c->anchor_y = o.shape.cy;
      ++o.n_moves;
      o.history.push_back({t, o.shape.cx, o.shape.cy});
      emit(t, scan_index, o, ObjectEvent::Moved);
    }
  }
}

bool ObjectTracker::withdraw(int id, double t, std::size_t scan_index) {
  if (id < 1 || id > static_cast<int>(objects_.size())) return false;
  TrackedObject& o = object(id);
  if (o.state != ObjectState::Absent) return false;
  o.state = ObjectState::Withdrawn;
  emit(t, scan_index, o, ObjectEvent::Withdrawn);
  return true;
}

PlaceView ObjectTracker::viewOfShape(const ScanView& view, const ShapeEstimate& s) const {
  const double margin = std::max(0.05, 2 * resolution_);  // range noise and the cell size
  // A beam ending on a cell S holds occupied hit a wall, not the object.
  const auto on_wall = [&](std::size_t i) {
    double x, y;
    hitPoint(view, i, x, y);
    return map_ != nullptr && map_->isStaticOccupied(map_->x2idx(x), map_->y2idx(y));
  };
  return viewOf(view, s.cx, s.cy, 0.5 * s.size, margin, on_wall);
}

bool ObjectTracker::nearKeepOut(const ShapeEstimate& shape) const {
  // A person walking or standing is no object: their cluster never becomes one.
  for (const KeepOut& k : keep_out_) {
    if (std::hypot(shape.cx - k.x, shape.cy - k.y) <= k.r) return true;
  }
  return false;
}

bool ObjectTracker::partOfASeenObject(const ShapeEstimate& shape, const ScanView& view) const {
  for (const auto& kv : tracks_) {
    const Confirmed* c = kv.second.confirmed();
    if (!c) continue;
    const TrackedObject& o = objects_[static_cast<std::size_t>(c->id - 1)];
    if (o.state != ObjectState::Present ||
        std::hypot(shape.cx - o.shape.cx, shape.cy - o.shape.cy) > reachOf(o.shape))
      continue;
    // Seen in place: its own cells hit by this scan (its disc may lie off them: a far arc's
    // centre), its disc seen occupied, or reported in this scan.
    if (beam_on_.count(kv.first) || reportedThisScan(c->id) ||
        viewOfShape(view, o.shape) == PlaceView::SeenOccupied) {
      return true;
    }
  }
  return false;
}

bool ObjectTracker::reportedThisScan(int id) const {
  for (std::size_t i = events_before_update_; i < events_.size(); ++i) {
    if (events_[i].object_id == id) return true;
  }
  return false;
}

}  // namespace dynamap
