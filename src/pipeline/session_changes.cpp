#include "dynamap/pipeline/session_changes.h"

#include <algorithm>
#include <cmath>

#include "dynamap/base/hungarian.h"
#include "dynamap/base/ini.h"
#include "dynamap/objects/shape.h"

namespace dynamap {

const OptionTable<ChangeOptions>& ChangeOptions::table() {
  using O = ChangeOptions;
  static const OptionTable<O> t(
      kSection,
      {
          {"structure_margin", &O::structure_margin, Range::closed(0, 2), "m",
           "a structure change this close to the other session's walls is their pose error"},
          {"structure_min_cells", &O::structure_min_cells, Range::closed(1, 1e6), "",
           "fewer cells are no structure change"},
          {"structure_stay_s", &O::structure_stay_s, Range::closed(0, 1e6), "s",
           "added structure: in D at least this long at the session's end"},
          {"removed_occupancy", &O::removed_occupancy, Range::closed(0.5, 1), "",
           "only cells the prior held occupied above this P(occ) can be removed or left"},
          {"gone_views", &O::gone_views, Range::closed(1, 1e6), "",
           "scans that saw a carried object's place empty before it is gone", 5},
      });
  return t;
}

void ChangeOptions::load(const IniFile& ini) {
  table().load(ini, *this);
}

void ChangeOptions::writeIni(std::ostream& out) const {
  table().write(*this, out);
}

SessionChanges::SessionChanges(SessionState prior, const ChangeOptions& options,
                               const ObjectOptions& objects)
    : options_(options), objects_(objects), prior_(std::move(prior)) {
  for (const SessionObject& o : prior_.objects) {
    if (o.state == "present") places_.push_back({o.id, o.cx, o.cy, o.size});
  }
}

namespace {

ChangeRow changeRow(const char* kind, int id, double size) {
  ChangeRow r;
  r.kind = kind;
  r.id = id;
  r.size = size;
  return r;
}

int globalOrigin(double min, double resolution) {
  return static_cast<int>(std::lround(min / resolution));
}

}  // namespace

void SessionChanges::update(const DynamicGridMap& map, const ScanView& view, double t) {
  last_t_ = t;
  const double res = map.getResolution();
  const int ox = globalOrigin(map.getXMin(), res), oy = globalOrigin(map.getYMin(), res);
  const auto sx = map.getSizeX();
  for (const std::uint32_t i : map.changedObjectCells()) {
    const int cx = static_cast<int>(i % sx), cy = static_cast<int>(i / sx);
    const CellKey k = cellKey(cx + ox, cy + oy);
    if (map.isObjectIndex(i)) {
      entered_.emplace(k, t);
    } else {
      entered_.erase(k);
    }
  }
  if (view.empty()) return;
  const double margin = std::max(0.05, 2 * res);  // as the tracker sees places
  for (Place& p : places_) {
    const PlaceView pv = viewOf(view, p.cx, p.cy, 0.5 * p.size, margin, [&](std::size_t b) {
      double x, y;
      hitPoint(view, b, x, y);
      return map.isStaticOccupied(map.x2idx(x), map.y2idx(y));
    });
    if (pv == PlaceView::SeenFree) ++p.seen_free;
    if (pv == PlaceView::SeenOccupied) ++p.seen_occupied;
  }
}

std::int8_t SessionChanges::priorCell(double x, double y) const {
  const double fx = std::floor((x - prior_.x_min) / prior_.resolution);
  const double fy = std::floor((y - prior_.y_min) / prior_.resolution);
  if (fx < 0 || fy < 0 || fx >= prior_.size_x || fy >= prior_.size_y) return 0;
  return prior_
      .static_cells[static_cast<std::size_t>(fx) + static_cast<std::size_t>(fy) * prior_.size_x];
}

std::vector<std::int8_t> SessionChanges::priorOnGrid(const DynamicGridMap& map) const {
  const unsigned sx = map.getSizeX(), sy = map.getSizeY();
  std::vector<std::int8_t> cells(static_cast<std::size_t>(sx) * sy, 0);
  const double fx = (map.getXMin() - prior_.x_min) / prior_.resolution;
  const double fy = (map.getYMin() - prior_.y_min) / prior_.resolution;
  const long ox = std::lround(fx), oy = std::lround(fy);
  const bool aligned = std::abs(map.getResolution() - prior_.resolution) < 1e-6 * prior_.resolution &&
                       std::abs(fx - ox) < 1e-3 && std::abs(fy - oy) < 1e-3;
  for (unsigned y = 0; y < sy; ++y) {
    const auto row = cells.begin() + static_cast<std::ptrdiff_t>(y) * sx;
    const long py = static_cast<long>(y) + oy;
    if (!aligned) {
      for (unsigned x = 0; x < sx; ++x) row[x] = priorCell(map.idx2x(x), map.idx2y(y));
    } else if (py >= 0 && py < static_cast<long>(prior_.size_y)) {
      // Map cell x is prior cell x + ox: copy where both grids hold it.
      const long x0 = std::max(0L, -ox), x1 = std::min<long>(sx, static_cast<long>(prior_.size_x) - ox);
      const auto src = prior_.static_cells.begin() + py * static_cast<long>(prior_.size_x) + ox;
      if (x0 < x1) std::copy(src + x0, src + x1, row + x0);
    }
  }
  return cells;
}

bool SessionChanges::onTablePlace(double x, double y) const {
  return std::any_of(prior_.objects.begin(), prior_.objects.end(), [&](const SessionObject& o) {
    const bool listed = o.state == "present" || o.state == "absent";
    return listed && std::hypot(o.cx - x, o.cy - y) <= 0.5 * o.size + prior_.resolution;
  });
}

bool SessionChanges::seenEmpty(const Place& p) const {
  return p.seen_free >= options_.gone_views && p.seen_free > p.seen_occupied;
}

void SessionChanges::carriedChanges(const ObjectTracker& tracker,
                                    std::vector<ChangeRow>& rows) const {
  // The tracker holds the carried rows from the first scan inserted on: none, nothing changed.
  if (tracker.objects().size() < prior_.objects.size()) return;
  for (std::size_t k = 0; k < prior_.objects.size(); ++k) {
    const TrackedObject& o = tracker.objects()[k];
    // A carried row's history starts with its carried place: more is what this session found.
    if (!listedInTable(o.state) || o.history.size() < 2) continue;
    const SessionObject& before = prior_.objects[k];
    if (std::hypot(o.shape.cx - before.cx, o.shape.cy - before.cy) <= objects_.move_distance)
      continue;
    // An object the prior held present moved only if its place was seen empty: else the id went
    // to something else of its size, and the object may well stand where it stood.
    const auto place =
        std::find_if(places_.begin(), places_.end(), [&](const Place& p) { return p.id == o.id; });
    if (place != places_.end() && !seenEmpty(*place)) continue;
    ChangeRow r = changeRow("object_moved", o.id, o.shape.size);
    r.from_x = before.cx;
    r.from_y = before.cy;
    r.to_x = o.shape.cx;
    r.to_y = o.shape.cy;
    r.first_seen_t = o.history[1].t;
    rows.push_back(r);
  }
  for (const Place& p : places_) {
    const TrackedObject& o = tracker.objects()[static_cast<std::size_t>(p.id - 1)];
    if (o.history.size() >= 2 || !seenEmpty(p)) continue;
    ChangeRow r = changeRow("object_gone", p.id, p.size);
    r.from_x = p.cx;
    r.from_y = p.cy;
    rows.push_back(r);
  }
}

void SessionChanges::objectChanges(const ObjectTracker& tracker, std::vector<ChangeRow> vacated,
                                   std::vector<ChangeRow>& rows) const {
  carriedChanges(tracker, rows);
  std::vector<const TrackedObject*> fresh;  // new to the table, present at the end
  for (std::size_t k = prior_.objects.size(); k < tracker.objects().size(); ++k) {
    const TrackedObject& o = tracker.objects()[k];
    // Not present: it came and went. Wider than an object: structure, reported as such.
    if (o.state == ObjectState::Present && o.shape.size <= objects_.max_size) fresh.push_back(&o);
  }
  // Which place each came from: identity by size, then distance, as one assignment. A place's
  // size is fitted to the S cells the prior held surely occupied, the middle of the arc it saw
  // (its ends, seen by fewer beams, fall short of removed_occupancy); an object's to all its D
  // cells. So an object may measure a cell more above its place's size than below it.
  constexpr double kForbidden = 1e9;
  const double below = objects_.size_tolerance, above = objects_.size_tolerance + prior_.resolution;
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(fresh.size()),
                       static_cast<Eigen::Index>(vacated.size()));
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    for (std::size_t v = 0; v < vacated.size(); ++v) {
      const ShapeEstimate& s = fresh[i]->shape;
      const double ds = s.size - vacated[v].size;
      const double d = std::hypot(vacated[v].from_x - s.cx, vacated[v].from_y - s.cy);
      // Across a building a size says little: farther than far_match_distance, no move.
      const bool fits = ds >= -below && ds <= above && d <= objects_.far_match_distance;
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(v)) =
          fits ? std::abs(ds - 0.5 * (above - below)) / (0.5 * (above + below)) +
                     d / objects_.match_distance_scale
               : kForbidden;
    }
  }
  const std::vector<int> from = solveAssignment(cost, kForbidden);
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    const TrackedObject& o = *fresh[i];
    ChangeRow r = changeRow(from[i] >= 0 ? "object_moved" : "object_new", o.id, o.shape.size);
    if (from[i] >= 0) {
      ChangeRow& v = vacated[static_cast<std::size_t>(from[i])];
      r.from_x = v.from_x;
      r.from_y = v.from_y;
      r.region = v.region;
      v.kind.clear();  // taken
    }
    r.to_x = o.shape.cx;
    r.to_y = o.shape.cy;
    r.first_seen_t = o.first_seen_t;
    rows.push_back(r);
  }
  for (ChangeRow& v : vacated) {  // an object of the prior's S, gone: it has no id
    // Seen through but not yet free: where an object of its size went, never alone a change.
    if (v.kind.empty() || v.kind == "vacated_seen_through") continue;
    v.kind = "object_gone";
    v.cells = 0;
    rows.push_back(v);
  }
}

namespace {

// A group of change cells (8-neighbours), in a grid's cell coordinates.
struct Region {
  std::vector<std::pair<int, int>> cells;
  double first_t = HUGE_VAL;
};

// The 8-connected groups of the cells `mask` marks, on a grid `sx` wide.
std::vector<Region> regionsOf(std::vector<std::uint8_t>& mask, int sx, int sy) {
  std::vector<Region> out;
  std::vector<std::pair<int, int>> stack;
  for (int y0 = 0; y0 < sy; ++y0) {
    for (int x0 = 0; x0 < sx; ++x0) {
      if (!mask[static_cast<std::size_t>(y0) * sx + x0]) continue;
      Region r;
      mask[static_cast<std::size_t>(y0) * sx + x0] = 0;
      stack.push_back({x0, y0});
      while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        r.cells.push_back({x, y});
        for (int ny = std::max(0, y - 1); ny <= std::min(sy - 1, y + 1); ++ny) {
          for (int nx = std::max(0, x - 1); nx <= std::min(sx - 1, x + 1); ++nx) {
            auto& m = mask[static_cast<std::size_t>(ny) * sx + nx];
            if (!m) continue;
            m = 0;
            stack.push_back({nx, ny});
          }
        }
      }
      out.push_back(std::move(r));
    }
  }
  return out;
}

// Whether any cell within `m` cells of (x, y) satisfies `test(nx, ny)`.
template <typename Test>
bool near(int x, int y, int m, Test test) {
  for (int ny = y - m; ny <= y + m; ++ny) {
    for (int nx = x - m; nx <= x + m; ++nx) {
      if (test(nx, ny)) return true;
    }
  }
  return false;
}

// The row of one region: its centre, its longest extent (box side plus a cell) and its cells.
ChangeRow rowOf(const Region& r, const char* kind, const DynamicGridMap& map) {
  const double res = map.getResolution();
  int x0 = r.cells[0].first, x1 = x0, y0 = r.cells[0].second, y1 = y0;
  double sx = 0, sy = 0;
  for (const auto& [x, y] : r.cells) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
    sx += map.idx2x(x);
    sy += map.idx2y(y);
  }
  ChangeRow row = changeRow(kind, 0, (std::max(x1 - x0, y1 - y0) + 1) * res);
  const double n = static_cast<double>(r.cells.size());
  (std::string(kind) == "structure_added" ? row.to_x : row.from_x) = sx / n;
  (std::string(kind) == "structure_added" ? row.to_y : row.from_y) = sy / n;
  row.cells = r.cells.size();
  row.region = r.cells;
  if (std::isfinite(r.first_t)) row.first_seen_t = r.first_t;
  return row;
}

// A region of an object's size where an object stood: its place and size as the tracker fits
// them (the region is the arc the earlier session saw, whose centroid lies off the object's
// centre), in a row of `kind`.
ChangeRow placeRow(const Region& r, const char* kind, const DynamicGridMap& map,
                   const ObjectOptions& objects) {
  const double res = map.getResolution();
  const int ox = globalOrigin(map.getXMin(), res), oy = globalOrigin(map.getYMin(), res);
  std::vector<CellXY> global;
  for (const auto& [x, y] : r.cells) global.push_back({x + ox, y + oy});
  const ShapeEstimate shape = estimateShape(global, res, objects);
  ChangeRow row = rowOf(r, kind, map);
  row.from_x = shape.cx;
  row.from_y = shape.cy;
  row.size = shape.size;
  return row;
}

// Largest first within a kind, numbered 1, 2, ... per kind.
void numberByKind(std::vector<ChangeRow>& found) {
  std::stable_sort(found.begin(), found.end(), [](const ChangeRow& a, const ChangeRow& b) {
    return a.kind != b.kind ? a.kind < b.kind : a.cells > b.cells;
  });
  for (std::size_t k = 0; k < found.size(); ++k) {
    found[k].id = k > 0 && found[k - 1].kind == found[k].kind ? found[k - 1].id + 1 : 1;
  }
}

}  // namespace

void SessionChanges::structureChanges(const DynamicGridMap& map, std::vector<ChangeRow>& rows,
                                      std::vector<ChangeRow>& vacated) const {
  const int sx = static_cast<int>(map.getSizeX()), sy = static_cast<int>(map.getSizeY());
  const double res = map.getResolution();
  const int m = static_cast<int>(std::ceil(options_.structure_margin / res - 1e-9));
  const int ox = globalOrigin(map.getXMin(), res), oy = globalOrigin(map.getYMin(), res);
  const std::vector<std::int8_t> on_grid = priorOnGrid(map);
  const auto prior = [&](int x, int y) {  // off the map: off the prior's grid too, as it grew
    const bool in = x >= 0 && y >= 0 && x < sx && y < sy;
    return in ? on_grid[x + static_cast<std::size_t>(y) * sx] : priorCell(map.idx2x(x), map.idx2y(y));
  };
  const auto prior_occupied = [&](int x, int y) {
    return DynamicGridMap::isOccupiedValue(prior(x, y));
  };
  const auto now_occupied = [&](int x, int y) { return map.isStaticOccupied(x, y); };
  std::vector<std::uint8_t> added(static_cast<std::size_t>(sx) * sy, 0), removed(added.size(), 0);
  for (int y = 0; y < sy; ++y) {
    for (int x = 0; x < sx; ++x) {
      const std::int8_t p = prior(x, y);
      const std::size_t i = static_cast<std::size_t>(y) * sx + x;
      if (p >= map.freeThresholdCell() && map.isObjectIndex(i) && !near(x, y, m, prior_occupied)) {
        const auto e = entered_.find(cellKey(x + ox, y + oy));
        added[i] = e != entered_.end() && e->second <= last_t_ - options_.structure_stay_s;
      } else if (DynamicGridMap::staticOccupancyOfValue(p) > options_.removed_occupancy &&
                 map.isStaticFree(x, y)) {
        removed[i] = !near(x, y, m, now_occupied);
      }
    }
  }
  std::vector<ChangeRow> found;
  for (Region& r : regionsOf(added, sx, sy)) {
    for (const auto& [x, y] : r.cells)
      r.first_t = std::min(r.first_t, entered_.at(cellKey(x + ox, y + oy)));
    ChangeRow row = rowOf(r, "structure_added", map);
    if (row.size > objects_.max_size && static_cast<int>(row.cells) >= options_.structure_min_cells)
      found.push_back(row);
  }
  std::vector<std::uint8_t> taken(added.size(), 0);  // cells of the regions reported below
  for (const Region& r : regionsOf(removed, sx, sy)) {
    if (static_cast<int>(r.cells.size()) < options_.structure_min_cells) continue;
    for (const auto& [x, y] : r.cells) taken[x + static_cast<std::size_t>(y) * sx] = 1;
    const ChangeRow row = rowOf(r, "structure_removed", map);
    if (row.size > objects_.max_size) {
      found.push_back(row);
      continue;
    }
    // An object's size: a place an object left. Where the prior's table had an object, S's
    // cells are where it stood before it was seen moving: that object's business
    // (carriedChanges), no other object's origin.
    const ChangeRow place = placeRow(r, "vacated", map, objects_);
    if (!onTablePlace(place.from_x, place.from_y)) vacated.push_back(place);
  }
  seenThrough(map, on_grid, taken, vacated);
  numberByKind(found);
  rows.insert(rows.end(), found.begin(), found.end());
}

void SessionChanges::seenThrough(const DynamicGridMap& map, const std::vector<std::int8_t>& prior,
                                 const std::vector<std::uint8_t>& taken,
                                 std::vector<ChangeRow>& vacated) const {
  const int sx = static_cast<int>(map.getSizeX()), sy = static_cast<int>(map.getSizeY());
  // Space behind a surface is never seen while the surface stands: a cell the prior never saw
  // (its raw value still 0) that this session sees free lies where something no longer is.
  const auto behind = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < sx && y < sy && prior[x + static_cast<std::size_t>(y) * sx] == 0 &&
           map.isStaticFree(x, y);
  };
  std::vector<std::uint8_t> through(taken.size(), 0);
  for (int y = 0; y < sy; ++y) {
    for (int x = 0; x < sx; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * sx + x;
      through[i] = !taken[i] &&
                   DynamicGridMap::staticOccupancyOfValue(prior[i]) > options_.removed_occupancy &&
                   map.staticOccupancy(x, y) <= options_.removed_occupancy && near(x, y, 1, behind);
    }
  }
  for (const Region& r : regionsOf(through, sx, sy)) {
    if (static_cast<int>(r.cells.size()) < options_.structure_min_cells) continue;
    const ChangeRow place = placeRow(r, "vacated_seen_through", map, objects_);
    if (place.size <= objects_.max_size && !onTablePlace(place.from_x, place.from_y))
      vacated.push_back(place);
  }
}

SessionChanges::GridChanges SessionChanges::gridChanges(const DynamicGridMap& map) const {
  GridChanges g;
  structureChanges(map, g.structure, g.vacated);
  return g;
}

std::vector<ChangeRow> SessionChanges::report(const GridChanges& grid,
                                              const ObjectTracker& tracker) const {
  std::vector<ChangeRow> rows;
  objectChanges(tracker, grid.vacated, rows);
  rows.insert(rows.end(), grid.structure.begin(), grid.structure.end());
  return rows;
}

std::vector<ChangeRow> SessionChanges::report(const DynamicGridMap& map,
                                              const ObjectTracker& tracker) const {
  return report(gridChanges(map), tracker);
}

}  // namespace dynamap
