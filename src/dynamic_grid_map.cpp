#include "dynamap/dynamic_grid_map.h"

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamap/ray_cast.h"

namespace dynamap {
namespace {

using cellType = DynamicGridMap::cellType;
using Base = mrpt::maps::COccupancyGridMap2D;

constexpr int kCellMin = Base::OCCGRID_CELLTYPE_MIN;
constexpr int kCellMax = Base::OCCGRID_CELLTYPE_MAX;
constexpr double kLogOddsUnitsPerNat = 16.0;  // MRPT's integer log-odds scale

// What a beam contributes: a hit at its end cell, or only the cells it crossed.
enum BeamKind : std::uint8_t { kBeamNone = 0, kBeamFreeOnly = 1, kBeamHit = 2 };

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
  syncLayers();
}

void DynamicGridMap::resizeGrid(float new_x_min, float new_x_max, float new_y_min,
                                float new_y_max, float new_cells_default_value,
                                bool additionalMargin) noexcept {
  Base::resizeGrid(new_x_min, new_x_max, new_y_min, new_y_max, new_cells_default_value,
                   additionalMargin);
  syncLayers();
}

void DynamicGridMap::syncLayers() {
  if (m_size_x == layer_size_x_ && m_size_y == layer_size_y_ && m_xMin == layer_x_min_ &&
      m_yMin == layer_y_min_ && dyn_.size() == m_map.size()) {
    return;
  }
  std::vector<cellType> dyn(m_map.size(), 0);
  std::vector<std::uint32_t> stamp(m_map.size(), 0);
  if (!dyn_.empty()) {
    // The base grows by whole cells, so the old layer sits at an integer offset.
    const long ox = std::lround((layer_x_min_ - m_xMin) / m_resolution);
    const long oy = std::lround((layer_y_min_ - m_yMin) / m_resolution);
    for (std::uint32_t y = 0; y < layer_size_y_; ++y) {
      const long ny = static_cast<long>(y) + oy;
      if (ny < 0 || ny >= static_cast<long>(m_size_y)) continue;
      for (std::uint32_t x = 0; x < layer_size_x_; ++x) {
        const long nx = static_cast<long>(x) + ox;
        if (nx < 0 || nx >= static_cast<long>(m_size_x)) continue;
        const std::size_t from = x + static_cast<std::size_t>(y) * layer_size_x_;
        const std::size_t to = static_cast<std::size_t>(nx) + static_cast<std::size_t>(ny) * m_size_x;
        dyn[to] = dyn_[from];
        stamp[to] = stamp_[from];
      }
    }
  }
  dyn_.swap(dyn);
  stamp_.swap(stamp);
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
  layer_size_x_ = layer_size_y_ = 0;
  syncLayers();
}

float DynamicGridMap::dynamicOccupancy(int cx, int cy) const {
  if (static_cast<unsigned>(cx) >= m_size_x || static_cast<unsigned>(cy) >= m_size_y) return 0.5f;
  return 1.0f - l2p(dyn_[cx + static_cast<std::size_t>(cy) * m_size_x]);
}

float DynamicGridMap::staticOccupancy(int cx, int cy) const { return 1.0f - getCell(cx, cy); }

bool DynamicGridMap::isStaticFree(int cx, int cy) const {
  if (static_cast<unsigned>(cx) >= m_size_x || static_cast<unsigned>(cy) >= m_size_y) return false;
  return m_map[cx + static_cast<std::size_t>(cy) * m_size_x] >= free_cell_;
}

bool DynamicGridMap::isObjectCell(int cx, int cy) const {
  if (static_cast<unsigned>(cx) >= m_size_x || static_cast<unsigned>(cy) >= m_size_y) return false;
  return isObjectIndex(cx + static_cast<std::size_t>(cy) * m_size_x);
}

DynamicGridMap::CellCounts DynamicGridMap::countCells() const {
  CellCounts c;
  for (std::size_t i = 0; i < m_map.size(); ++i) {
    if (m_map[i] < 0) ++c.static_occupied;
    if (m_map[i] >= free_cell_) ++c.static_free;
    if (dyn_[i] < object_cell_) ++c.dynamic_occupied;
  }
  return c;
}

bool DynamicGridMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose) {
  changed_.clear();
  last_stats_ = {};
  if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs)) {
    return insertScan(*scan, robotPose ? *robotPose : mrpt::poses::CPose3D());
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

inline void DynamicGridMap::applyHit(std::size_t index) {
  const cellType s = m_map[index];
  const cellType d = dyn_[index];
  if (s >= free_cell_) {  // S knew this cell as free: something moved in
    m_map[index] = clampCell(s + deltas_.s_hit_free, kCellMin);
    dyn_[index] = clampCell(d + deltas_.d_hit_free, d_floor_, d_ceiling_);
  } else {  // NotFree: consistent with a static part of the world
    m_map[index] = clampCell(s + deltas_.s_hit_notfree, kCellMin);
    dyn_[index] = clampCell(d + deltas_.d_hit_notfree, d_floor_, d_ceiling_);
  }
  noteChange(index, d);
}

inline void DynamicGridMap::applyMiss(std::size_t index) {
  const cellType d = dyn_[index];
  m_map[index] = clampCell(m_map[index] + deltas_.s_miss, kCellMin);
  dyn_[index] = clampCell(d + deltas_.d_miss, d_floor_, d_ceiling_);
  noteChange(index, d);
}

bool DynamicGridMap::insertScan(const mrpt::obs::CObservation2DRangeScan& scan,
                                const mrpt::poses::CPose3D& robot_pose) {
  const double tolerance = insertion_.horizontal_tolerance_deg * M_PI / 180.0;
  if (!scan.isPlanarScan(tolerance)) return false;
  const std::size_t n = scan.getScanSize();
  if (n == 0 || !(scan.aperture > 0.0f) || !std::isfinite(scan.aperture)) return false;

  m_likelihoodCacheOutDated = true;
  const mrpt::poses::CPose3D sensor3d = robot_pose + scan.sensorPose;
  const mrpt::poses::CPose2D sensor(sensor3d);
  // A sensor mounted upside down sweeps the other way round.
  const bool upside_down =
      sensor3d.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>()(2, 2) < 0;
  const double first = n > 1 ? -0.5 * scan.aperture : 0.0;  // a lone beam looks ahead
  const double step = n > 1 ? scan.aperture / static_cast<double>(n - 1) : 0.0;
  const double dir = (scan.rightToLeft ^ upside_down) ? 1.0 : -1.0;
  const float max_range = static_cast<float>(insertion_.max_distance_insertion);

  // 1. Beam end points in the map frame, and the box that must fit in the grid.
  end_x_.resize(n);
  end_y_.resize(n);
  end_kind_.assign(n, kBeamNone);
  const float px = static_cast<float>(sensor.x());
  const float py = static_cast<float>(sensor.y());
  float min_x = px, max_x = px, min_y = py, max_y = py;
  float last_valid = max_range;
  for (std::size_t i = 0; i < n; ++i) {
    const float r = scan.getScanRange(i);
    float reach = 0;
    if (scan.getScanRangeValidity(i)) {
      if (!std::isfinite(r) || r < 0.0f) {
        ++last_stats_.beams_bad;
        continue;
      }
      reach = std::min(max_range, r);
      end_kind_[i] = r < max_range ? kBeamHit : kBeamFreeOnly;
      last_valid = r;
    } else if (insertion_.invalid_ranges_as_free) {
      reach = std::min(max_range, 0.5f * last_valid);
      end_kind_[i] = kBeamFreeOnly;
    } else {
      continue;
    }
    const double a = sensor.phi() + dir * (first + step * static_cast<double>(i));
    end_x_[i] = px + static_cast<float>(std::cos(a)) * reach;
    end_y_[i] = py + static_cast<float>(std::sin(a)) * reach;
    min_x = std::min(min_x, end_x_[i]);
    max_x = std::max(max_x, end_x_[i]);
    min_y = std::min(min_y, end_y_[i]);
    max_y = std::max(max_y, end_y_[i]);
  }

  // 2. Grow S and D together when the scan reaches past the grid (with one cell of slack).
  const float slack = m_resolution;
  if (min_x < m_xMin + slack || max_x > m_xMax - slack || min_y < m_yMin + slack ||
      max_y > m_yMax - slack) {
    resizeGrid(min_x - slack, max_x + slack, min_y - slack, max_y + slack, 0.5f, true);
  }

  // 3. A new stamp marks the cells this scan has updated.
  if (++scan_stamp_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    scan_stamp_ = 1;
  }
  const std::uint32_t stamp = scan_stamp_;
  const std::size_t size_x = m_size_x;

  // 4. Hits first, so a hit beats a miss of another beam in the same cell.
  for (std::size_t i = 0; i < n; ++i) {
    if (end_kind_[i] != kBeamHit) continue;
    const std::size_t idx = x2idx(end_x_[i]) + static_cast<std::size_t>(y2idx(end_y_[i])) * size_x;
    if (stamp_[idx] == stamp) continue;
    stamp_[idx] = stamp;
    applyHit(idx);
    ++last_stats_.hit_cells;
  }

  // 5. Then the cells each beam crossed, each at most once.
  const int cx0 = x2idx(px);
  const int cy0 = y2idx(py);
  std::uint32_t freed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (end_kind_[i] == kBeamNone) continue;
    ++last_stats_.beams_used;
    traceRay(cx0, cy0, x2idx(end_x_[i]), y2idx(end_y_[i]), [&](int cx, int cy) {
      const std::size_t idx = cx + static_cast<std::size_t>(cy) * size_x;
      if (stamp_[idx] == stamp) return;
      stamp_[idx] = stamp;
      applyMiss(idx);
      ++freed;
    });
  }
  last_stats_.free_cells = freed;
  last_stats_.inserted = last_stats_.beams_used > 0;
  return last_stats_.inserted;
}

}  // namespace dynamap
