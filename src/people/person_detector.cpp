#include "dynamap/people/person_detector.h"

#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "dynamap/base/cell_key.h"
#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/people/leg_classifier.h"

namespace dynamap {

ScanHits scanHits(const RangeData& rd, const mrpt::poses::CPose2D& robot) {
  ScanHits h;
  scanHits(rd, robot, h);
  return h;
}

void scanHits(const RangeData& rd, const mrpt::poses::CPose2D& robot, ScanHits& h) {
  const std::size_t n = rd.size();
  h.points.clear();
  const mrpt::poses::CPose2D sensor = rd.sensorIn(mrpt::poses::CPose3D(robot));
  h.sensor_x = sensor.x();
  h.sensor_y = sensor.y();
  // A beam without an echo saw nothing as far as the sensor reaches, not as far as the grid
  // inserts: a person just out of the sensor's range is unseen, not seen gone.
  h.max_range = rd.sensor_max_range > 0 ? std::min(rd.insertion_range, rd.sensor_max_range)
                                        : rd.insertion_range;
  h.step = std::abs(rd.step);
  h.ranges.resize(n);
  h.angles.resize(n);
  h.cosines.resize(n);
  h.sines.resize(n);
  // Each beam's direction in the map frame is the sensor's heading turned by the beam's angle,
  // whose cos and sin RangeData keeps: no trigonometry per beam.
  const double c = std::cos(sensor.phi()), s = std::sin(sensor.phi());
  const auto max_range = static_cast<float>(rd.insertion_range);
  for (std::size_t i = 0; i < n; ++i) {
    h.angles[i] = sensor.phi() + rd.angle(i);
    h.cosines[i] = c * rd.cos_angle[i] - s * rd.sin_angle[i];
    h.sines[i] = s * rd.cos_angle[i] + c * rd.sin_angle[i];
    const BeamKind kind = rd.kinds[i];
    const bool echo = kind == BeamKind::Hit || kind == BeamKind::Beyond;
    h.ranges[i] = echo ? std::min(rd.ranges[i], max_range) : -1.0f;
    // An echo at the cut-off is where the insertion stops, not a surface.
    if (kind != BeamKind::Hit) continue;
    const double r = rd.ranges[i];
    h.points.push_back({h.sensor_x + r * h.cosines[i], h.sensor_y + r * h.sines[i], i});
  }
}

ScanHits scanHits(const mrpt::obs::CObservation2DRangeScan& scan, const mrpt::poses::CPose2D& robot,
                  double max_range) {
  return scanHits(makeRangeData(scan, max_range, M_PI), robot);
}

namespace {

// The cell of `p` in (cx, cy); false off the grid, where S knows nothing. Compared as
// coordinates first: a far point's cell index does not fit an int (converting it is undefined).
bool cellOf(const DynamicGridMap& map, const HitPoint2& p, int& cx, int& cy) {
  if (!(p.x >= map.getXMin() && p.x < map.getXMax() && p.y >= map.getYMin() && p.y < map.getYMax()))
    return false;
  cx = map.x2idx(p.x);
  cy = map.y2idx(p.y);
  return cx >= 0 && cy >= 0 && cx < static_cast<int>(map.getSizeX()) &&
         cy < static_cast<int>(map.getSizeY());
}

}  // namespace

std::vector<HitPoint2> freeSpaceHits(const DynamicGridMap& map, const ScanHits& hits, int guard) {
  std::vector<HitPoint2> out;
  for (const HitPoint2& p : hits.points) {
    int cx = 0, cy = 0;
    if (!cellOf(map, p, cx, cy)) continue;
    // The hit's own cell first: on a wall (most hits) it is not free, and that settles it.
    bool free = map.isStaticFree(cx, cy);
    for (int dy = -guard; dy <= guard && free; ++dy) {
      for (int dx = -guard; dx <= guard && free; ++dx) free = map.isStaticFree(cx + dx, cy + dy);
    }
    if (free) out.push_back(p);
  }
  return out;
}

namespace {

// The largest distance between two of the points, or any value above `cap` once it is known to
// exceed it (such a cluster is no person: its exact width does not matter).
double spread(const std::vector<HitPoint2>& pts, std::size_t begin, std::size_t end, double cap) {
  double widest = 0;
  for (std::size_t i = begin; i < end; ++i) {
    for (std::size_t j = begin; j < i; ++j) {
      widest = std::max(widest, std::hypot(pts[i].x - pts[j].x, pts[i].y - pts[j].y));
    }
    if (widest > cap) return widest;
  }
  return widest;
}

// The points' centroid pushed away from the sensor: the beams see the near half of a round body,
// whose points lie on average pi/4 of its radius in front of its centre.
PointCluster summarise(const std::vector<HitPoint2>& pts, std::size_t begin, std::size_t end,
                       double sx, double sy, double max_width) {
  PointCluster c;
  c.points = end - begin;
  double mx = 0, my = 0;
  for (std::size_t i = begin; i < end; ++i) {
    mx += pts[i].x;
    my += pts[i].y;
  }
  c.width = spread(pts, begin, end, max_width);
  // Each edge lies between the last beam that hit and the next one: half a beam gap beyond.
  if (c.points > 1) c.width += c.width / static_cast<double>(c.points - 1);
  mx /= static_cast<double>(c.points);
  my /= static_cast<double>(c.points);
  const double d = std::hypot(mx - sx, my - sy);
  const double push = d > 0 ? 0.25 * M_PI * 0.5 * c.width / d : 0.0;
  c.cx = mx + (mx - sx) * push;
  c.cy = my + (my - sy) * push;
  return c;
}

}  // namespace

std::vector<PointCluster> clusterPoints(const std::vector<HitPoint2>& pts, double sx, double sy,
                                        const PeopleOptions& o, double beam_step) {
  std::vector<PointCluster> out;
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= pts.size(); ++i) {
    bool split = i == pts.size() || pts[i].beam > pts[i - 1].beam + 2;
    if (!split) {
      const double range = std::hypot(pts[i].x - sx, pts[i].y - sy);
      const double join = std::max(o.cluster_distance, 2.0 * range * beam_step);
      split = std::hypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y) > join;
    }
    if (!split) continue;
    if (i - begin >= static_cast<std::size_t>(o.min_points)) {
      out.push_back(summarise(pts, begin, i, sx, sy, o.max_person_width));
    }
    begin = i;
  }
  return out;
}

std::vector<PersonDetection> pairLegs(const std::vector<PointCluster>& clusters,
                                      const PeopleOptions& o) {
  std::vector<std::size_t> legs;
  std::vector<PersonDetection> out;
  for (std::size_t i = 0; i < clusters.size(); ++i) {
    if (clusters[i].width <= o.max_leg_width) {
      legs.push_back(i);
    } else if (clusters[i].width <= o.max_person_width) {
      out.push_back({clusters[i].cx, clusters[i].cy, 0});
    }
  }
  // Every pair of legs close enough, nearest first (ties by index: deterministic).
  struct Pair {
    double d;
    std::size_t a, b;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < legs.size(); ++i) {
    for (std::size_t j = i + 1; j < legs.size(); ++j) {
      const PointCluster &a = clusters[legs[i]], &b = clusters[legs[j]];
      const double d = std::hypot(a.cx - b.cx, a.cy - b.cy);
      if (d <= o.leg_pair_distance) pairs.push_back({d, i, j});
    }
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Pair& p, const Pair& q) { return p.d < q.d; });
  std::vector<char> used(legs.size(), 0);
  for (const Pair& p : pairs) {
    if (used[p.a] || used[p.b]) continue;
    used[p.a] = used[p.b] = 1;
    const PointCluster &a = clusters[legs[p.a]], &b = clusters[legs[p.b]];
    out.push_back({0.5 * (a.cx + b.cx), 0.5 * (a.cy + b.cy), 2});
  }
  for (std::size_t i = 0; i < legs.size(); ++i) {
    if (!used[i]) out.push_back({clusters[legs[i]].cx, clusters[legs[i]].cy, 1});
  }
  return out;
}

namespace {

// object_max_extent in cells.
int objectExtentCells(const DynamicGridMap& map, const PeopleOptions& o) {
  return static_cast<int>(std::ceil(o.object_max_extent / map.getResolution()));
}

// A set of cell keys for one scan's searches: open addressing in a table that doubles when half
// full, so an insert allocates only when the table grows (a node-based set allocates per cell,
// and a wall met near a detection is hundreds of cells).
class CellSet {
 public:
  CellSet() : table_(kInitial, kEmpty) {}
  bool count(CellKey key) const {
    for (std::size_t i = slot(key);; i = (i + 1) & (table_.size() - 1)) {
      if (table_[i] == key) return true;
      if (table_[i] == kEmpty) return false;
    }
  }
  void insert(CellKey key) {
    if (2 * (size_ + 1) > table_.size()) grow();
    place(key);
  }

 private:
  // No cell of a grid has the most negative x index: never a key.
  static constexpr CellKey kEmpty = std::numeric_limits<CellKey>::min();
  static constexpr std::size_t kInitial = 1024;
  std::size_t slot(CellKey key) const {
    const auto h = static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull;
    return static_cast<std::size_t>(h >> 32) & (table_.size() - 1);
  }
  void place(CellKey key) {
    std::size_t i = slot(key);
    while (table_[i] != kEmpty && table_[i] != key) i = (i + 1) & (table_.size() - 1);
    if (table_[i] == kEmpty) ++size_;
    table_[i] = key;
  }
  void grow() {
    std::vector<CellKey> previous(2 * table_.size(), kEmpty);
    previous.swap(table_);  // table_ is now twice as large and empty
    size_ = 0;
    for (const CellKey k : previous) {
      if (k != kEmpty) place(k);
    }
  }
  std::vector<CellKey> table_;
  std::size_t size_ = 0;
};

// The cells one search of smallStaticBlob met, marked in a window around where it started (the
// search never leaves it: it stops once the body is `extent` cells wide), kept between searches
// so that a scan's searches allocate nothing after the first.
class BlobMarks {
 public:
  explicit BlobMarks(int extent) : half_(extent + 2), side_(2 * half_ + 1) {
    marks_.assign(static_cast<std::size_t>(side_) * static_cast<std::size_t>(side_), 0);
  }
  void start(int cx, int cy) {
    for (const auto& [x, y] : cells_) marks_[index(x, y)] = 0;
    cells_.clear();
    cx_ = cx;
    cy_ = cy;
  }
  /// Marks (x, y); false when it was marked already.
  bool insert(int x, int y) {
    char& m = marks_[index(x, y)];
    if (m) return false;
    m = 1;
    cells_.emplace_back(x, y);
    return true;
  }
  const std::vector<std::pair<int, int>>& cells() const { return cells_; }
  /// The search's own stack, kept for its capacity.
  std::vector<std::pair<int, int>>& todo() { return todo_; }

 private:
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y - cy_ + half_) * static_cast<std::size_t>(side_) +
           static_cast<std::size_t>(x - cx_ + half_);
  }
  int half_, side_;
  int cx_ = 0, cy_ = 0;
  std::vector<char> marks_;
  std::vector<std::pair<int, int>> cells_, todo_;
};

// Whether the cells S holds occupied connected to (cx, cy) all fit in a square of `extent`
// cells: a body that could be moved (a bin, a chair), not a wall. Stops as soon as they do not,
// so a wall costs a few dozen cells, and adds the cells it met to `large`: a search from another
// cell of the same wall stops as soon as it meets one of them.
bool smallStaticBlob(const DynamicGridMap& map, int cx, int cy, int extent,
                     CellSet& large, BlobMarks& seen) {
  seen.start(cx, cy);
  seen.insert(cx, cy);
  std::vector<std::pair<int, int>>& todo = seen.todo();
  todo.assign(1, {cx, cy});
  int x0 = cx, x1 = cx, y0 = cy, y1 = cy;
  bool small = true;
  while (!todo.empty() && small) {
    const auto [x, y] = todo.back();
    todo.pop_back();
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    small = x1 - x0 < extent && y1 - y0 < extent && !large.count(cellKey(x, y));
    // Cells up to 2 apart are one body: a wall seen from afar has a free cell between two hits.
    // (isStaticOccupied's test, a row at a time: this loop is most of a scan's detection.)
    const int size_x = static_cast<int>(map.getSizeX());
    for (int dy = -2; dy <= 2 && small; ++dy) {
      const DynamicGridMap::cellType* row = map.getRow(y + dy);
      if (row == nullptr) continue;
      for (int dx = std::max(-2, -x); dx <= 2 && x + dx < size_x; ++dx) {
        if (DynamicGridMap::isOccupiedValue(row[x + dx]) && seen.insert(x + dx, y + dy))
          todo.emplace_back(x + dx, y + dy);
      }
    }
  }
  if (!small) {
    for (const auto& [x, y] : seen.cells()) large.insert(cellKey(x, y));
  }
  return small;
}

// Calls f(cx, cy) for each cell whose centre lies within `radius` of (x, y)'s cell, row by row;
// true as soon as f returns true. A centre farther than `radius` off the grid has no cell within
// reach: it is told by its coordinates, as its cell index need not fit an int (a leg found among
// hits far off the grid; converting it is undefined).
template <typename F>
bool anyCellWithin(const DynamicGridMap& map, double x, double y, double radius, F&& f) {
  if (!(x >= map.getXMin() - radius && x <= map.getXMax() + radius &&
        y >= map.getYMin() - radius && y <= map.getYMax() + radius)) {
    return false;
  }
  const double res = map.getResolution();
  const int n = static_cast<int>(std::ceil(radius / res));
  const int cx = map.x2idx(x), cy = map.y2idx(y);
  for (int dy = -n; dy <= n; ++dy) {
    for (int dx = -n; dx <= n; ++dx) {
      if ((dx * dx + dy * dy) * res * res > radius * radius) continue;
      if (f(cx + dx, cy + dy)) return true;
    }
  }
  return false;
}

bool nearStatic(const DynamicGridMap& map, double x, double y, const PeopleOptions& o,
                CellSet& large, BlobMarks& seen) {
  const int extent = objectExtentCells(map, o);
  return anyCellWithin(map, x, y, o.static_clearance, [&](int cx, int cy) {
    // An object D holds, or a small body in S: something that stood here and may be moving
    // off, not someone walking. A wall (a larger body of S) is passed by people all the time.
    return map.isObjectCell(cx, cy) ||
           (map.isStaticOccupied(cx, cy) && !large.count(cellKey(cx, cy)) &&
            smallStaticBlob(map, cx, cy, extent, large, seen));
  });
}

// Whether a beam of `h` passes through the cell of half-width `half` centred at (x, y) and
// ends more than `margin` beyond it: the scan sees through what S holds there.
bool seenThrough(const ScanHits& h, double x, double y, double half, double margin) {
  if (h.angles.size() < 2) return false;
  const double step = std::remainder(h.angles[1] - h.angles[0], 2 * M_PI);
  if (std::abs(step) < 1e-9) return false;
  const double dx = x - h.sensor_x, dy = y - h.sensor_y;
  const double k = std::round(std::remainder(std::atan2(dy, dx) - h.angles[0], 2 * M_PI) / step);
  if (k < 0 || k >= static_cast<double>(h.angles.size())) return false;
  const auto i = static_cast<std::size_t>(k);
  const bool cached = h.cosines.size() == h.angles.size() && h.sines.size() == h.angles.size();
  const double c = cached ? h.cosines[i] : std::cos(h.angles[i]);
  const double s = cached ? h.sines[i] : std::sin(h.angles[i]);
  const double along = dx * c + dy * s, perp = std::abs(dx * s - dy * c);
  if (along <= 0 || perp >= half) return false;
  const double range = h.ranges[i] < 0 ? h.max_range : h.ranges[i];
  return range > along + half + margin;
}

// Whether this scan sees through static_left_cells cells S holds occupied within
// static_clearance of (x, y) (see PersonDetection::static_left).
bool staticLeft(const DynamicGridMap& map, const ScanHits& hits, double x, double y,
                const PeopleOptions& o) {
  const double res = map.getResolution();
  int seen = 0;
  return anyCellWithin(map, x, y, o.static_clearance, [&](int cx, int cy) {
    if (!map.isStaticOccupied(cx, cy)) return false;
    const double x0 = map.getXMin() + (cx + 0.5) * res, y0 = map.getYMin() + (cy + 0.5) * res;
    return seenThrough(hits, x0, y0, 0.5 * res, o.static_left_margin) &&
           ++seen >= o.static_left_cells;
  });
}

}  // namespace

namespace {

// Whether most points of `s` lie on cells S holds occupied: what the map knows as standing there.
bool onStatic(const DynamicGridMap& map, const ScanHits& hits, const Segment& s) {
  std::size_t occupied = 0;
  for (std::size_t i = s.begin; i < s.end; ++i) {
    int cx = 0, cy = 0;
    if (cellOf(map, hits.points[i], cx, cy)) occupied += map.isStaticOccupied(cx, cy) ? 1 : 0;
  }
  return 2 * occupied > s.size();
}

}  // namespace

std::vector<PersonDetection> shapeDetections(const DynamicGridMap& map, const ScanHits& hits,
                                             const PeopleOptions& o, const LegClassifier& legs) {
  std::vector<PointCluster> clusters;
  for (const Segment& s : segmentScan(hits, kLegSegmentJump, kLegMinPoints)) {
    const HitPoint2 &a = hits.points[s.begin], &b = hits.points[s.end - 1];
    // Only what could be a person at all reaches the classifier (most of a scan is walls).
    if (std::hypot(a.x - b.x, a.y - b.y) > o.max_person_width || onStatic(map, hits, s)) continue;
    if (!legs.isLeg(legFeatures(hits, s), o.leg_probability)) continue;
    clusters.push_back(
        summarise(hits.points, s.begin, s.end, hits.sensor_x, hits.sensor_y, o.max_person_width));
  }
  std::vector<PersonDetection> out = pairLegs(clusters, o);
  for (PersonDetection& d : out) d.shape = true;
  return out;
}

double shareOfHits(std::size_t n, const ScanHits& hits) {
  return hits.points.empty() ? 0.0
                             : static_cast<double>(n) / static_cast<double>(hits.points.size());
}

double freeSurfaceShare(const std::vector<HitPoint2>& free, const ScanHits& hits,
                        const PeopleOptions& o, double length) {
  PeopleOptions wide = o;
  wide.max_person_width = length;  // a cluster's width is measured up to this
  std::size_t on = 0;
  for (const PointCluster& c : clusterPoints(free, hits.sensor_x, hits.sensor_y, wide, hits.step)) {
    if (c.width > length) on += c.points;
  }
  return shareOfHits(on, hits);
}

std::vector<PersonDetection> detectPeople(const DynamicGridMap& map, const ScanHits& hits,
                                          const PeopleOptions& o, const LegClassifier* legs,
                                          std::vector<HitPoint2>* free_hits) {
  std::vector<HitPoint2> free = freeSpaceHits(map, hits, o.wall_guard_cells);
  std::vector<PersonDetection> out =
      pairLegs(clusterPoints(free, hits.sensor_x, hits.sensor_y, o, hits.step), o);
  if (free_hits != nullptr) *free_hits = std::move(free);
  if (legs != nullptr) {
    const std::size_t seen = out.size();
    for (PersonDetection d : shapeDetections(map, hits, o, *legs)) {
      d.leg_shaped = d.legs == 2;
      bool known = false;
      for (std::size_t i = 0; i < seen; ++i) {
        if (std::hypot(out[i].x - d.x, out[i].y - d.y) > 0.5 * o.leg_pair_distance) continue;
        known = true;
        out[i].leg_shaped = out[i].leg_shaped || d.leg_shaped;
      }
      if (!known) out.push_back(d);
    }
  }
  CellSet large;  // cells of S's walls met so far, for every detection
  BlobMarks seen(objectExtentCells(map, o));
  for (PersonDetection& d : out) {
    d.near_static = nearStatic(map, d.x, d.y, o, large, seen);
    // Near a small body it is judged as an object may be already: the wall case is the one left.
    d.static_left = !d.near_static && staticLeft(map, hits, d.x, d.y, o);
  }
  return out;
}

}  // namespace dynamap
