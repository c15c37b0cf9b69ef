#include "dynamap/objects/object_tracker.h"
// The object tracker's first half: from D's cells above the threshold to tracks (the dirty cells
// folded in, re-clustered, each cluster's shape and the points the scan put on it). The second
// half, tracks to objects and their table, is object_tracker.cpp.

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {

void ObjectTracker::foldChanges(const DynamicGridMap& map, std::vector<CellKey>& dirty) {
  resolution_ = map.getResolution();
  origin_x_ = static_cast<int>(std::lround(map.getXMin() / resolution_));
  origin_y_ = static_cast<int>(std::lround(map.getYMin() / resolution_));
  const std::size_t sx = map.getSizeX();
  for (const std::uint32_t idx : map.changedObjectCells()) {
    const int cx = static_cast<int>(idx % sx), cy = static_cast<int>(idx / sx);
    const CellKey k = cellKey(cx + origin_x_, cy + origin_y_);
    if (map.isObjectIndex(idx)) {
      cells_.insert(k);
    } else {
      cells_.erase(k);
    }
    dirty.push_back(k);
  }
}

bool ObjectTracker::isWallNoise(const DynamicGridMap& map, CellXY c) const {
  return options_.wall_hug_distance > 0 && nearNotFree(map, c, options_.wall_hug_distance);
}

bool ObjectTracker::nearNotFree(const DynamicGridMap& map, CellXY c, double distance) const {
  const double rc = distance / resolution_;
  const int r = static_cast<int>(std::floor(rc + 1e-9));
  const double r2 = rc * rc;
  const int gx = c.x - origin_x_, gy = c.y - origin_y_;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > r2 + 1e-9) continue;
      if (!map.isStaticFree(gx + dx, gy + dy)) return true;
    }
  }
  return false;
}

bool ObjectTracker::shortOfCells(const Track& tr) const {
  return options_.support_threshold > 0 && !tr.cells.empty() &&
         static_cast<int>(tr.cells.size()) < options_.min_cells;
}

int ObjectTracker::supportCells(const DynamicGridMap& map, const Track& tr) const {
  if (!shortOfCells(tr)) return 0;
  const auto offsets = joinOffsets(options_.join_distance / resolution_);
  std::set<CellKey> seen;
  for (const CellKey k : tr.cells) {
    const CellXY c = cellOf(k);
    for (const CellXY& o : offsets) {
      const CellXY n{c.x + o.x, c.y + o.y};
      const CellKey nk = cellKey(n.x, n.y);
      const int gx = n.x - origin_x_, gy = n.y - origin_y_;
      if (cells_.count(nk) || !map.isStaticFree(gx, gy) ||
          map.dynamicOccupancy(gx, gy) < options_.support_threshold || isWallNoise(map, n)) {
        continue;
      }
      seen.insert(nk);
    }
  }
  return static_cast<int>(seen.size());
}

int ObjectTracker::ownerOfMost(const std::vector<CellXY>& cluster) const {
  std::map<int, std::size_t> votes;
  for (const CellXY& c : cluster) {
    const auto it = owner_.find(cellKey(c.x, c.y));
    if (it != owner_.end()) ++votes[it->second];
  }
  int best = 0;
  std::size_t most = 0;
  for (const auto& kv : votes) {
    if (kv.second > most) best = kv.first, most = kv.second;
  }
  return best;
}

int ObjectTracker::followedTrack(const ShapeEstimate& s) const {
  int best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& kv : tracks_) {
    const Track& tr = kv.second;
    if (tr.isStale() || tr.cells.empty()) continue;
    const ShapeEstimate& shape = shapeOf(tr);
    const double d = std::hypot(shape.cx - s.cx, shape.cy - s.cy);
    if (d <= reachOf(shape) && d < best_d) {
      best_d = d;
      best = kv.first;
    }
  }
  return best;
}

double ObjectTracker::reachOf(const ShapeEstimate& object) const {
  return 0.5 * object.size + options_.follow_margin;
}

bool ObjectTracker::usable(const DynamicGridMap& map, CellKey k) {
  if (!cells_.count(k)) return false;
  auto it = noise_memo_.find(k);
  if (it == noise_memo_.end()) it = noise_memo_.emplace(k, isWallNoise(map, cellOf(k))).first;
  return !it->second;
}

void ObjectTracker::recluster(const DynamicGridMap& map, const std::vector<CellKey>& dirty) {
  noise_memo_.clear();  // S may have changed since the last scan
  // Tracks that lose cells: owners of faded cells.
  std::set<int> touched;
  for (const CellKey k : dirty) {
    const auto it = owner_.find(k);
    if (it != owner_.end() && !cells_.count(k)) {
      touched.insert(it->second);
      owner_.erase(it);
    }
  }
  std::unordered_set<CellKey> visited;
  // Each cluster to the track owning most of its cells, or to a track it continues, or new.
  std::map<int, std::vector<CellKey>> gained;
  for (const auto& cl : clustersNear(map, dirty, visited)) {
    for (const CellXY& c : cl) {
      const auto it = owner_.find(cellKey(c.x, c.y));
      if (it != owner_.end()) touched.insert(it->second);
    }
    int key = ownerOfMost(cl);
    if (!key) key = followedTrack(estimateShape(cl, resolution_, options_));
    if (!key) {
      key = next_track_++;
      tracks_[key] = Track{};
    }
    touched.insert(key);
    auto& g = gained[key];
    for (const CellXY& c : cl) {
      g.push_back(cellKey(c.x, c.y));
      owner_[g.back()] = key;
    }
  }
  for (const int key : touched) {
    const auto g = gained.find(key);
    rebuild(map, key, visited, g == gained.end() ? std::vector<CellKey>{} : g->second);
  }
}

std::vector<std::vector<CellXY>> ObjectTracker::clustersNear(const DynamicGridMap& map,
                                                             const std::vector<CellKey>& dirty,
                                                             std::unordered_set<CellKey>& visited) {
  const auto offsets = joinOffsets(options_.join_distance / resolution_);
  const auto use = [&](CellKey k) { return usable(map, k); };
  // Every cluster within reach of a changed cell (a removed cell may have split its cluster:
  // each part still has a cell within the join distance of it).
  std::vector<std::vector<CellXY>> clusters;
  for (const CellKey k : dirty) {
    const CellXY c = cellOf(k);
    for (std::size_t i = 0; i <= offsets.size(); ++i) {
      const CellKey n = i == offsets.size() ? k : cellKey(c.x + offsets[i].x, c.y + offsets[i].y);
      if (visited.count(n) || !use(n)) continue;
      clusters.push_back(growCluster(n, offsets, use, visited));
    }
  }
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) {
    return cellKey(a[0].x, a[0].y) < cellKey(b[0].x, b[0].y);
  });
  return clusters;
}

void ObjectTracker::rebuild(const DynamicGridMap& map, int key,
                            const std::unordered_set<CellKey>& visited,
                            const std::vector<CellKey>& gained) {
  Track& tr = tracks_[key];
  // Its kept cells (untouched by this scan's clusters) plus its gains.
  std::vector<CellKey> cells;
  for (const CellKey k : tr.cells) {
    if (visited.count(k) || !cells_.count(k)) continue;
    const auto it = owner_.find(k);
    if (it != owner_.end() && it->second == key) cells.push_back(k);
  }
  cells.insert(cells.end(), gained.begin(), gained.end());
  std::sort(cells.begin(), cells.end());
  tr.cells.swap(cells);
  refresh(tr, resolution_);
  tr.hugs_wall = false;
  const double reach = options_.wall_hug_distance + 2 * resolution_;  // noise cells left out
  for (std::size_t i = 0; i < tr.cells.size() && !tr.hugs_wall && reach > 0; ++i) {
    tr.hugs_wall = nearNotFree(map, cellOf(tr.cells[i]), reach);
  }
  touched_.insert(key);
}

void ObjectTracker::refresh(Track& tr, double res) {
  if (tr.cells.empty()) return;
  ShapeEstimate s = measureShape(tr, res, sensor_x_, sensor_y_, options_);
  applyOutline(tr.outline, s);
  if (Confirmed* c = tr.confirmed()) {
    ShapeEstimate& row = object(c->id).shape;
    // A fading object keeps the estimate made from the most cells: its last cells are a part.
    if (s.cells < c->best_cells) {
      applyOutline(tr.outline, row);  // but its outlines still size it
      return;
    }
    c->best_cells = s.cells;
    row = s;
    return;
  }
  if (Stale* st = tr.stale()) st->best_cells = std::max(st->best_cells, s.cells);
  *tr.ownShape() = s;
}

const ShapeEstimate& ObjectTracker::shapeOf(const Track& tr) const {
  if (const ShapeEstimate* own = tr.ownShape()) return *own;
  return objects_[static_cast<std::size_t>(tr.objectId() - 1)].shape;
}

int ObjectTracker::trackOf(int id) const {
  for (const auto& kv : tracks_) {
    if (kv.second.objectId() == id) return kv.first;
  }
  return 0;
}

bool ObjectTracker::onObjectCell(const DynamicGridMap& map, double x, double y) const {
  const double tx = (x - map.getXMin()) / map.getResolution();
  const double ty = (y - map.getYMin()) / map.getResolution();
  constexpr double kEdge = 1e-6;  // [cells] far above rounding, far below a cell
  const auto onEdge = [](double t) {
    const double f = t - std::floor(t);
    return f < kEdge || f > 1 - kEdge;
  };
  if (!std::isfinite(tx) || !std::isfinite(ty) || onEdge(tx) || onEdge(ty)) return true;
  const int cx = map.x2idx(x), cy = map.y2idx(y);
  if (cx < 0 || cy < 0 || cx >= static_cast<int>(map.getSizeX()) ||
      cy >= static_cast<int>(map.getSizeY()))
    return false;
  // D's own test first: a beam that ends on no object cell (most) costs no hash lookup. The
  // tracker's object cells are D's (foldChanges keeps them so), so this drops nothing.
  return map.isObjectCell(cx, cy) && owner_.count(cellKey(cx + origin_x_, cy + origin_y_)) != 0;
}

void ObjectTracker::collectPoints(const DynamicGridMap& map, const ScanView& view) {
  beam_on_.clear();
  if (view.empty() || owner_.empty()) return;
  const double bin = 0.01;  // [m] one point kept per bin: the latest
  std::set<int> fed;
  const std::size_t n = view.ranges.size();
  const bool cached = view.cosines.size() == n && view.sines.size() == n;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = view.ranges[i];
    if (r <= 0.0 || r >= view.max_range) continue;
    // Most beams end on no object cell: the cached direction tells, without a sine and cosine
    // each. It can differ from the exact one only in the last bits, which never changes the
    // cell unless the point lies on a cell's edge: there, and on object cells, it is exact.
    if (cached && !onObjectCell(map, view.x + r * view.cosines[i], view.y + r * view.sines[i]))
      continue;
    double x, y;
    hitPoint(view, i, x, y);
    const int cx = map.x2idx(x), cy = map.y2idx(y);
    if (cx < 0 || cy < 0 || cx >= static_cast<int>(map.getSizeX()) ||
        cy >= static_cast<int>(map.getSizeY())) {
      continue;
    }
    const CellKey cell = cellKey(cx + origin_x_, cy + origin_y_);
    const auto it = owner_.find(cell);
    if (it == owner_.end() || !cells_.count(cell)) continue;
    const CellKey b =
        cellKey(static_cast<int>(std::floor(x / bin)), static_cast<int>(std::floor(y / bin)));
    Track& tr = tracks_[it->second];
    if (shapeOf(tr).length > options_.max_size) continue;  // a wall: no finer size needed
    beam_on_.emplace(it->second, i);
    auto& points = tr.points;
    const bool fresh = points.find(b) == points.end();
    points[b] = {x, y, r * std::abs(view.step), cell};
    if (fresh) fed.insert(it->second);  // a point where none was: the arc grew
  }
  for (const int key : fed) {
    refresh(tracks_[key], resolution_);
    touched_.insert(key);  // a better size may now pass the filters
  }
}

void ObjectTracker::updateLastSeen(const ScanView& view, double t) {
  if (view.empty()) return;
  for (TrackedObject& o : objects_) {
    if (o.state != ObjectState::Present) continue;
    if (viewOfShape(view, o.shape) == PlaceView::SeenOccupied) {
      o.last_seen_t = t;
    }
  }
}

}  // namespace dynamap
