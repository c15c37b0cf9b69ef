#include "dynamap/mapping/dynamic_grid_map.h"

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "dynamap/mapping/polygon_fill.h"

namespace dynamap {

// Filled from MRPT's own table on first use of the library (MRPT builds it on its first call).
const std::array<float, 256> DynamicGridMap::kCellProbability = [] {
  std::array<float, 256> t{};
  for (int v = -128; v < 128; ++v) t[static_cast<std::uint8_t>(v)] = l2p(static_cast<cellType>(v));
  return t;
}();
const std::array<std::uint8_t, 256> DynamicGridMap::kCellGrey = [] {
  std::array<std::uint8_t, 256> t{};
  for (int v = -128; v < 128; ++v) t[static_cast<std::uint8_t>(v)] = l2p_255(static_cast<cellType>(v));
  return t;
}();

namespace {

using cellType = DynamicGridMap::cellType;
using Base = mrpt::maps::COccupancyGridMap2D;

constexpr int kCellMin = Base::OCCGRID_CELLTYPE_MIN;
constexpr int kCellMax = Base::OCCGRID_CELLTYPE_MAX;
constexpr double kLogOddsUnitsPerNat = 16.0;  // MRPT's integer log-odds scale

inline cellType clampCell(int v, int lo, int hi = kCellMax) {
  return static_cast<cellType>(v < lo ? lo : (v > hi ? hi : v));
}

// Smallest integer cell whose P(free) passes `pass` (cells are ordered by P(free)).
template <typename Pass>
cellType firstCellWhere(Pass pass) {
  for (int c = kCellMin; c <= kCellMax; ++c) {
    if (pass(Base::l2p(static_cast<cellType>(c)))) return static_cast<cellType>(c);
  }
  return static_cast<cellType>(kCellMax);
}

}  // namespace

int logOddsFreeStep(double p_occupied) {
  return -static_cast<int>(
      std::lround(kLogOddsUnitsPerNat * std::log(p_occupied / (1.0 - p_occupied))));
}

DynamicGridMap::DynamicGridMap(const DynamicMapOptions& options, const InsertionOptions& insertion,
                               float x_min, float x_max, float y_min, float y_max)
    : Base(x_min, x_max, y_min, y_max, static_cast<float>(options.resolution)),
      options_(options),
      insertion_(insertion) {
  options_.validate("DynamicGridMap options");
  insertion_.validate("DynamicGridMap insertion options");
  deltas_ = {logOddsFreeStep(options_.s_hit_notfree), logOddsFreeStep(options_.s_hit_free),
             logOddsFreeStep(options_.s_miss),        logOddsFreeStep(options_.d_hit_free),
             logOddsFreeStep(options_.d_hit_notfree), logOddsFreeStep(options_.d_miss)};
  // Free: P(occ) < free_threshold, i.e. P(free) > 1 - free_threshold: cells >= free_cell_.
  const float free_p = static_cast<float>(1.0 - options_.free_threshold);
  free_cell_ = firstCellWhere([&](float p) { return p > free_p; });
  // Object: P(occ) > object_threshold, i.e. P(free) < 1 - object_threshold: cells < object_cell_.
  const float object_p = static_cast<float>(1.0 - options_.object_threshold);
  object_cell_ = firstCellWhere([&](float p) { return p >= object_p; });
  d_floor_ = static_cast<cellType>(std::max(kCellMin, logOddsFreeStep(options_.d_max)));
  d_ceiling_ = static_cast<cellType>(std::min(kCellMax, logOddsFreeStep(options_.d_min)));
  // A miss is the same update whatever S's state: tabulate it, indexed by the cell's bits.
  for (int c = kCellMin - 1; c <= kCellMax; ++c) {
    const auto bits = static_cast<std::uint8_t>(static_cast<cellType>(c));
    miss_s_[bits] = clampCell(c + deltas_.s_miss, kCellMin);
    miss_d_[bits] = clampCell(c + deltas_.d_miss, d_floor_, d_ceiling_);
  }
  // The same updates as steps, for span()'s 16 cells at a time: only when each step fits a cell.
  const auto fits = [](int delta) { return delta >= kCellMin - 1 && delta <= kCellMax; };
  simd_steps_ = fits(deltas_.s_miss) && fits(deltas_.d_miss);
  if (simd_steps_) {
    MissLanes& l = lanes_;
    for (int i = 0; i < 16; ++i) {
      l.object_cell[i] = object_cell_;
      l.s_delta[i] = static_cast<cellType>(deltas_.s_miss);
      l.s_lo[i] = static_cast<cellType>(kCellMin);
      l.s_hi[i] = static_cast<cellType>(kCellMax);
      l.d_delta[i] = static_cast<cellType>(deltas_.d_miss);
      l.d_lo[i] = d_floor_;
      l.d_hi[i] = d_ceiling_;
    }
  }
  syncLayers();
}

void DynamicGridMap::resizeGrid(float new_x_min, float new_x_max, float new_y_min, float new_y_max,
                                float new_cells_default_value, bool additionalMargin) noexcept {
  Base::resizeGrid(new_x_min, new_x_max, new_y_min, new_y_max, new_cells_default_value,
                   additionalMargin);
  syncLayers();
}

void DynamicGridMap::setSize(float x_min, float x_max, float y_min, float y_max, float resolution,
                             float default_value) {
  Base::setSize(x_min, x_max, y_min, y_max, resolution, default_value);
  syncLayers();
}

void DynamicGridMap::loadStatic(double x_min, double y_min, double resolution, unsigned size_x,
                                unsigned size_y, const std::vector<std::int8_t>& cells) {
  if (std::abs(resolution - m_resolution) > 1e-6 * m_resolution) {
    throw std::invalid_argument("its resolution " + std::to_string(resolution) +
                                " m is not [dynamic_map] resolution " +
                                std::to_string(m_resolution) + " m");
  }
  if (cells.size() != static_cast<std::size_t>(size_x) * size_y) {
    throw std::invalid_argument("its cells do not fill its grid");
  }
  const double w = size_x * resolution, h = size_y * resolution;
  if (w > maxGridSide(options_) || h > maxGridSide(options_)) {
    throw std::invalid_argument("its grid is wider than [dynamic_map] max_map_size_m");
  }
  dyn_.clear();  // D starts empty: syncLayers() makes a fresh layer
  layer_size_x_ = layer_size_y_ = 0;
  // MRPT rounds each bound to a whole number of cells: a grid MRPT laid out comes back as it was.
  Base::setSize(static_cast<float>(x_min), static_cast<float>(x_min + w), static_cast<float>(y_min),
                static_cast<float>(y_min + h), static_cast<float>(resolution), 0.5f);
  if (m_size_x != size_x || m_size_y != size_y ||
      std::abs(m_xMin - x_min) > 0.01 * resolution || std::abs(m_yMin - y_min) > 0.01 * resolution) {
    throw std::invalid_argument("its grid's geometry cannot be laid out at this resolution");
  }
  std::copy(cells.begin(), cells.end(), m_map.begin());
  syncLayers();
}

bool DynamicGridMap::layersAligned() const {
  return m_size_x == layer_size_x_ && m_size_y == layer_size_y_ && m_xMin == layer_x_min_ &&
         m_yMin == layer_y_min_ && dyn_.size() == m_map.size();
}

void DynamicGridMap::syncLayers() {
  if (layersAligned()) return;
  std::vector<cellType> dyn(m_map.size(), 0);
  if (!dyn_.empty()) {
    // The base grows by whole cells, so the old layer sits at an integer offset.
    const long ox = std::lround((layer_x_min_ - m_xMin) / m_resolution);
    const long oy = std::lround((layer_y_min_ - m_yMin) / m_resolution);
    // Copy the overlap row by row.
    const long x_lo = std::max(0L, -ox), x_hi = std::min<long>(layer_size_x_, m_size_x - ox);
    for (std::uint32_t y = 0; y < layer_size_y_ && x_lo < x_hi; ++y) {
      const long ny = static_cast<long>(y) + oy;
      if (ny < 0 || ny >= static_cast<long>(m_size_y)) continue;
      const auto src = dyn_.begin() + static_cast<long>(y) * layer_size_x_;
      std::copy(src + x_lo, src + x_hi, dyn.begin() + ny * static_cast<long>(m_size_x) + x_lo + ox);
    }
  }
  dyn_.swap(dyn);
  // Marks only matter within one scan and the grid grows before a scan sets any: start afresh.
  stamp_.assign(m_map.size(), 0);
  stamped_box_ = {};
  layer_x_min_ = m_xMin;
  layer_y_min_ = m_yMin;
  layer_size_x_ = m_size_x;
  layer_size_y_ = m_size_y;
  changed_.clear();
}

void DynamicGridMap::internal_clear() {
  Base::internal_clear();
  dyn_.clear();
  stamp_.clear();
  stamped_box_ = {};
  layer_size_x_ = layer_size_y_ = 0;
  syncLayers();
}

float DynamicGridMap::dynamicOccupancy(int cx, int cy) const {
  // D's own geometry: the same as S's but for a resize of S alone (layersAligned()).
  if (static_cast<unsigned>(cx) >= layer_size_x_ || static_cast<unsigned>(cy) >= layer_size_y_)
    return 0.5f;
  return 1.0f - cellProbability(dyn_[cx + static_cast<std::size_t>(cy) * layer_size_x_]);
}

float DynamicGridMap::staticOccupancy(int cx, int cy) const {
  if (static_cast<unsigned>(cx) >= m_size_x || static_cast<unsigned>(cy) >= m_size_y) return 0.5f;
  return staticOccupancyOfValue(m_map[cx + static_cast<std::size_t>(cy) * m_size_x]);
}

DynamicGridMap::CellCounts DynamicGridMap::countCells() const {
  CellCounts c;
  for (std::size_t i = 0; i < m_map.size(); ++i) {
    if (isOccupiedValue(m_map[i])) ++c.static_occupied;
    if (m_map[i] >= free_cell_) ++c.static_free;
  }
  for (const cellType d : dyn_) c.dynamic_occupied += d < object_cell_ ? 1 : 0;
  return c;
}

bool DynamicGridMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs,
    const std::optional<const mrpt::poses::CPose3D>& robotPose) {
  changed_.clear();
  last_stats_ = {};
  if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs)) {
    insertion_.rangeData(*scan, range_);
    syncLayers();  // after a resize of S alone (see layersAligned)
    return insertScan(range_, robotPose ? *robotPose : mrpt::poses::CPose3D());
  }
  // Anything else is MRPT's business; keep D aligned if it grew the grid.
  const bool done = Base::internal_insertObservation(obs, robotPose);
  syncLayers();
  return done;
}

inline void DynamicGridMap::noteChange(std::size_t index, cellType before) {
  if ((before < object_cell_) != (dyn_[index] < object_cell_)) {
    changed_.push_back(static_cast<std::uint32_t>(index));
  }
}

bool DynamicGridMap::hitInFreeSpace(std::size_t index) const {
  if (m_map[index] < free_cell_) return false;
  // A hit beside a cell S holds occupied is far likelier the wall, seen through range noise or
  // a grazing beam, than an object standing within a cell of it.
  const int g = static_cast<int>(options_.wall_guard_cells);
  const int cx = static_cast<int>(index % m_size_x), cy = static_cast<int>(index / m_size_x);
  for (int y = std::max(0, cy - g); y <= std::min<int>(m_size_y - 1, cy + g); ++y) {
    for (int x = std::max(0, cx - g); x <= std::min<int>(m_size_x - 1, cx + g); ++x) {
      if (isOccupiedValue(m_map[x + static_cast<std::size_t>(y) * m_size_x])) return false;
    }
  }
  return true;
}

inline void DynamicGridMap::applyHit(std::size_t index, bool in_free_space) {
  const cellType s = m_map[index];
  const cellType d = dyn_[index];
  if (in_free_space) {  // S knew this cell as free: something moved in
    m_map[index] = clampCell(s + deltas_.s_hit_free, kCellMin);
    if (!hold_dynamic_) dyn_[index] = clampCell(d + deltas_.d_hit_free, d_floor_, d_ceiling_);
  } else {  // NotFree: consistent with a static part of the world
    m_map[index] = clampCell(s + deltas_.s_hit_notfree, kCellMin);
    dyn_[index] = clampCell(d + deltas_.d_hit_notfree, d_floor_, d_ceiling_);
  }
  noteChange(index, d);
}

bool DynamicGridMap::insertRange(const RangeData& rd, const mrpt::poses::CPose2D& robot) {
  syncLayers();  // after a resize of S alone (see layersAligned)
  changed_.clear();
  last_stats_ = {};
  return insertScan(rd, mrpt::poses::CPose3D(robot));
}

bool DynamicGridMap::insertScan(const RangeData& rd, const mrpt::poses::CPose3D& robot_pose) {
  last_stats_.skip_reason = "not horizontal";
  if (!rd.planar) return false;
  last_stats_.skip_reason = "no beams";
  if (rd.size() == 0) return false;
  last_stats_.skip_reason = kTooManyBeams;
  if (rd.size() > kMaxScanBeams) return false;
  last_stats_.skip_reason = "aperture not positive";
  if (!(rd.aperture > 0.0) || !std::isfinite(rd.aperture)) return false;
  if (rd.cos_angle.size() != rd.size() || rd.sin_angle.size() != rd.size()) {
    throw std::invalid_argument("DynamicGridMap: range data without its beam directions");
  }
  last_stats_.skip_reason = "pose not finite";
  for (double v : {robot_pose.x(), robot_pose.y(), robot_pose.yaw()}) {
    if (!std::isfinite(v)) return false;
  }

  const mrpt::poses::CPose2D sensor = computeBeams(rd, robot_pose);  // 1. where beams end
  if (!std::isfinite(sensor.x()) || !std::isfinite(sensor.y()) || !std::isfinite(sensor.phi())) {
    last_stats_.skip_reason = "sensor pose not finite";  // the scan's own mount, from a file
    return false;
  }
  last_stats_.skip_reason = "beyond max_map_size_m";
  if (!growToFit(sensor)) return false;  // 2. room for them
  m_likelihoodCacheOutDated = true;
  nextStamp();      // 3. a fresh scan mark
  applyHits();      // 4. hits first
  guardSurfaces();  // 5. how far each beam frees
  planWedges();     // 6. area between beams
  sweepFreeArea(sensor);
  traceBeamTails(sensor);  // 7. each beam beyond it
  last_stats_.inserted = last_stats_.beams_used > 0;
  last_stats_.skip_reason = last_stats_.inserted ? nullptr : "no usable beam";
  return last_stats_.inserted;
}

mrpt::poses::CPose2D DynamicGridMap::computeBeams(const RangeData& rd,
                                                  const mrpt::poses::CPose3D& robot_pose) {
  const std::size_t n = rd.size();
  const mrpt::poses::CPose2D sensor = rd.sensorIn(robot_pose);
  const float max_range = static_cast<float>(insertion_.max_distance_insertion);
  // Kept from scan to scan: every field a later step reads is set below or by that step (a beam
  // left kBeamNone is read for its kind alone).
  beams_.resize(n);
  float last_valid = max_range;
  last_stats_.beams_bad = rd.bad_beams;
  const double c = std::cos(sensor.phi()), s = std::sin(sensor.phi());
  for (std::size_t i = 0; i < n; ++i) {
    Beam& b = beams_[i];
    b.kind = kBeamNone;
    b.reach = 0;
    // The beam's direction turned by the sensor's heading.
    b.cos = c * rd.cos_angle[i] - s * rd.sin_angle[i];
    b.sin = s * rd.cos_angle[i] + c * rd.sin_angle[i];
    const float r = rd.ranges[i];
    switch (rd.kinds[i]) {
      case BeamKind::Bad:
        continue;
      case BeamKind::Hit:
      case BeamKind::Beyond:
        b.reach = std::min(max_range, r);
        b.kind = rd.kinds[i] == BeamKind::Hit ? kBeamHit : kBeamFreeOnly;
        last_valid = r;
        break;
      case BeamKind::NoEcho:
        if (!insertion_.invalid_ranges_as_free) continue;
        b.reach = std::min(max_range, 0.5f * last_valid);
        b.kind = kBeamFreeOnly;
        break;
    }
    b.end_x = static_cast<float>(sensor.x() + b.cos * b.reach);
    b.end_y = static_cast<float>(sensor.y() + b.sin * b.reach);
  }
  return sensor;
}

bool DynamicGridMap::growToFit(const mrpt::poses::CPose2D& sensor) {
  float min_x = static_cast<float>(sensor.x()), max_x = min_x;
  float min_y = static_cast<float>(sensor.y()), max_y = min_y;
  for (const Beam& b : beams_) {
    if (b.kind == kBeamNone) continue;
    min_x = std::min(min_x, b.end_x);
    max_x = std::max(max_x, b.end_x);
    min_y = std::min(min_y, b.end_y);
    max_y = std::max(max_y, b.end_y);
  }
  const float slack = m_resolution;  // one cell, so every end point is strictly inside
  if (min_x < m_xMin + slack || max_x > m_xMax - slack || min_y < m_yMin + slack ||
      max_y > m_yMax - slack) {
    // A pose jump in a log must not make the grid allocate without bound.
    const double limit = options_.max_map_size_m;
    if (std::max<double>(max_x, m_xMax) - std::min<double>(min_x, m_xMin) > limit ||
        std::max<double>(max_y, m_yMax) - std::min<double>(min_y, m_yMin) > limit) {
      return false;
    }
    resizeGrid(min_x - slack, max_x + slack, min_y - slack, max_y + slack, 0.5f, true);
  }
  // Every cell the scan updates lies between the sensor and the end points.
  scan_box_ = {x2idx(min_x), y2idx(min_y), x2idx(max_x), y2idx(max_y)};
  return true;
}

void DynamicGridMap::CellBox::add(const CellBox& b) {
  if (b.x1 < b.x0) return;
  if (x1 < x0) {
    *this = b;
    return;
  }
  x0 = std::min(x0, b.x0);
  y0 = std::min(y0, b.y0);
  x1 = std::max(x1, b.x1);
  y1 = std::max(y1, b.y1);
}

void DynamicGridMap::nextStamp() {
  if (++scan_stamp_ == 0) {  // every 255 scans: start the marks again
    const CellBox& b = stamped_box_;
    for (int y = b.y0; y <= b.y1 && b.x0 <= b.x1; ++y) {
      const auto row = stamp_.begin() + static_cast<std::ptrdiff_t>(y) * m_size_x;
      std::fill(row + b.x0, row + b.x1 + 1, std::uint8_t{0});
    }
    stamped_box_ = {};
    scan_stamp_ = 1;
  }
  stamped_box_.add(scan_box_);
}

void DynamicGridMap::applyHits() {
  // Judge every hit cell against S as it was before this scan, then update them.
  hits_.clear();
  for (const Beam& b : beams_) {
    if (b.kind != kBeamHit) continue;
    const std::size_t idx = x2idx(b.end_x) + static_cast<std::size_t>(y2idx(b.end_y)) * m_size_x;
    if (stamp_[idx] == scan_stamp_) continue;
    stamp_[idx] = scan_stamp_;
    hits_.push_back({idx, hitInFreeSpace(idx)});
  }
  for (const auto& [idx, in_free_space] : hits_) applyHit(idx, in_free_space);
  last_stats_.hit_cells = static_cast<std::uint32_t>(hits_.size());
}

namespace {
// Incidence below 1 degree: the neighbour's end point lies on another surface (a depth jump).
const double kMinSurfaceSin2 = std::sin(M_PI / 180.0) * std::sin(M_PI / 180.0);
}  // namespace

void DynamicGridMap::guardSurfaces() {
  // The surface a beam hit runs towards its neighbours' end points (when they hit too); across
  // that surface, range noise and the cell grid spread its hits over a band about a cell wide.
  // A beam meeting the surface at incidence a crosses a band of width surface_guard over
  // surface_guard / sin(a) of its length, a beam at right angles over surface_guard: the
  // difference is left unfreed, so a beam grazing a wall stops freeing before it reaches the
  // wall's cells. Of the two neighbours the one that gives the steeper incidence wins, so the edge
  // of an object in front of a wall (where one neighbour lies on another surface) keeps the short
  // guard of the surface the beam did hit, and a neighbour seen at less than a degree is a depth
  // jump, not this surface.
  const double guard = options_.surface_guard;
  const double guard_max = std::max(guard, options_.surface_guard_max);
  const std::size_t n = beams_.size();
  for (std::size_t i = 0; i < n; ++i) {
    Beam& b = beams_[i];
    b.stop = b.reach;
    if (b.kind != kBeamHit || guard <= 0.0) continue;
    double sin2 = -1.0;  // sin(a)^2 of the steeper neighbour; none known yet
    for (const std::size_t j : {i - 1, i + 1}) {
      if (j >= n || beams_[j].kind != kBeamHit) continue;  // i - 1 wraps round at i = 0
      const double tx = beams_[j].end_x - b.end_x, ty = beams_[j].end_y - b.end_y;
      const double len2 = tx * tx + ty * ty;
      if (len2 <= 0.0) continue;
      const double cross = b.cos * ty - b.sin * tx;
      const double s2 = cross * cross / len2;
      // Nearly along the beam: a depth jump to another surface, not the one hit.
      if (s2 >= kMinSurfaceSin2) sin2 = std::max(sin2, s2);
    }
    if (sin2 <= 0.0) continue;  // no neighbour on the surface: as at right angles
    const double sin_a = std::sqrt(sin2);
    // What the slant adds to the band's crossing, compared with a beam at right angles (whose
    // cells up to the end cell are freed, as MRPT does).
    const double along = std::min(guard_max, guard / std::max(sin_a, 1e-6) - guard);
    b.stop = static_cast<float>(std::max(0.0, b.reach - along));
  }
}

void DynamicGridMap::planWedges() {
  // A wedge spans kWedgeBeams adjacent beam gaps and is surely free up to the shortest of its
  // beams, less a cell so that end cells (and a wall between two end points) are left to the
  // beams themselves. Wider wedges mean fewer polygon corners, narrower ones shorter tails;
  // 8 measured best on indoor logs (4 and 16 within a few percent).
  const std::size_t n = beams_.size();
  wedges_.clear();
  for (Beam& b : beams_) b.covered = 0.0;
  if (n < 2) return;
  for (std::size_t first = 0; first + 1 < n; first += kWedgeBeams) {
    const std::size_t last = std::min(first + kWedgeBeams, n - 1);
    float shortest = std::numeric_limits<float>::max();
    for (std::size_t i = first; i <= last && shortest > 0.0f; ++i) {
      shortest = beams_[i].kind == kBeamNone ? 0.0f : std::min(shortest, beams_[i].stop);
    }
    const double radius = std::max(0.0, static_cast<double>(shortest) - m_resolution);
    wedges_.push_back({first, last, radius});
    // A beam is covered up to the smaller radius of the wedges it borders or lies in.
    for (std::size_t i = first; i <= last; ++i) {
      const bool shared = (i == first && first > 0);
      beams_[i].covered = shared ? std::min(beams_[i].covered, radius) : radius;
    }
  }
  beams_.front().covered = 0.0;  // the outermost beams bound the swept area: trace them whole
  beams_.back().covered = 0.0;
}

void DynamicGridMap::sweepFreeArea(const mrpt::poses::CPose2D& sensor) {
  // The star polygon: the sensor, then each wedge's two corners at its radius.
  const double inv_res = 1.0 / m_resolution;
  const GridPoint s{(sensor.x() - m_xMin) * inv_res, (sensor.y() - m_yMin) * inv_res};
  polygon_.clear();
  polygon_.push_back(s);
  for (const Wedge& w : wedges_) {
    const double rho = w.radius * inv_res;
    if (rho <= 0.0) {
      if (polygon_.back().u != s.u || polygon_.back().v != s.v) polygon_.push_back(s);
      continue;
    }
    for (const Beam* b : {&beams_[w.first], &beams_[w.last]}) {
      polygon_.push_back({s.u + rho * b->cos, s.v + rho * b->sin});
    }
  }
  if (polygon_.size() < 3) return;
  const MissKernel miss = missKernel();
  const std::size_t size_x = m_size_x;
  std::uint32_t freed = 0;
  fillPolygon(polygon_, static_cast<int>(m_size_x), static_cast<int>(m_size_y), fill_scratch_,
              [&miss, &freed, size_x](int cy, int cx_begin, int cx_end) {
                const std::size_t row = static_cast<std::size_t>(cy) * size_x;
                freed += miss.span(row + cx_begin, row + cx_end);
              });
  last_stats_.free_cells += freed;
}

DynamicGridMap::MissKernel DynamicGridMap::missKernel() {
  std::fill(std::begin(lanes_.mark), std::end(lanes_.mark), static_cast<cellType>(scan_stamp_));
  return {m_map.data(),   dyn_.data(),    stamp_.data(),
          miss_s_.data(), miss_d_.data(), scan_stamp_,
          object_cell_,   &changed_,      simd_steps_ ? &lanes_ : nullptr,
          m_map.size()};
}

void DynamicGridMap::traceBeamTails(const mrpt::poses::CPose2D& sensor) {
  const std::size_t size_x = m_size_x;
  const MissKernel miss = missKernel();
  std::uint32_t freed = 0;
  for (std::size_t i = 0; i < beams_.size(); ++i) {
    const Beam& b = beams_[i];
    if (b.kind == kBeamNone) continue;
    ++last_stats_.beams_used;
    // Start a cell before the swept area stops covering the beam, so the two join up.
    const double from = std::max(0.0, b.covered - m_resolution);
    if (b.stop < from) continue;  // the surface guard reaches back into the swept area
    const double sx = sensor.x() + b.cos * from;
    const double sy = sensor.y() + b.sin * from;
    const bool whole = b.stop >= b.reach;
    const double ex = whole ? b.end_x : sensor.x() + b.cos * b.stop;
    const double ey = whole ? b.end_y : sensor.y() + b.sin * b.stop;
    freed += miss.ray(x2idx(sx), y2idx(sy), x2idx(ex), y2idx(ey), size_x);
  }
  last_stats_.free_cells += freed;
}

}  // namespace dynamap
