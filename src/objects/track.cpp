#include "dynamap/objects/track.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynamap {

namespace {
constexpr std::size_t kFitPoints = 200;  // points a shape is fitted to, at most
}  // namespace

ShapeEstimate measureShape(Track& tr, double res, double sensor_x, double sensor_y,
                           const ObjectOptions& options) {
  std::vector<CellXY> xy;
  xy.reserve(tr.cells.size());
  for (const CellKey k : tr.cells) xy.push_back(cellOf(k));
  ShapeEstimate s = estimateShape(xy, res, options);
  // The hit points in its cells, when there are enough, measure it to the centimetre.
  // A cluster longer than any object (a wall seen off by localisation) needs no finer size.
  if (s.length > options.max_size) tr.points.clear();
  for (auto it = tr.points.begin(); it != tr.points.end();) {
    if (std::binary_search(tr.cells.begin(), tr.cells.end(), it->second.cell)) {
      ++it;
    } else {
      it = tr.points.erase(it);  // its cell left the object: a point of the past
    }
  }
  // At most kFitPoints, evenly through the bins, keep the fit's cost bounded.
  const std::size_t stride = tr.points.size() / kFitPoints + 1;
  std::vector<double> px, py;
  double gap = std::numeric_limits<double>::infinity();  // the nearest view's beam spacing
  std::size_t i = 0;
  for (const auto& kv : tr.points) {
    gap = std::min(gap, kv.second.gap);
    if (i++ % stride != 0) continue;
    px.push_back(kv.second.x);
    py.push_back(kv.second.y);
  }
  ShapeEstimate fine;
  if (estimatePointShape(px, py, gap, sensor_x, sensor_y, options, fine)) {
    fine.cells = s.cells;  // the filters and the fading rule count cells
    fine.thickness = s.thickness;
    fine.length = s.length;
    s = fine;
  }
  return s;
}

void SettledRun::pass(double size, double settle_size) {
  const bool settled = std::abs(size - last_size) <= settle_size;
  last_size = size;
  passes = settled ? passes + 1 : 1;
}

void OutlineSizes::add(double size, double g) {
  const double weight = 1.0 / std::max(g * g, 1e-6);
  ++count;
  w += weight;
  ws += weight * size;
  wss += weight * size * size;
  gap = count == 1 ? g : std::min(gap, g);
}

double OutlineSizes::error() const {
  const double mean = size();
  const double spread = std::sqrt(std::max(0.0, wss / w - mean * mean));
  return std::max(spread, 0.5 * gap) / std::sqrt(static_cast<double>(count));
}

void applyOutline(const OutlineSizes& outline, ShapeEstimate& s) {
  // A circle fitted to its arc measures it; only the width of a part seen falls short.
  if (outline.count == 0 || s.circle || outline.size() <= s.size) return;
  s.size = outline.size();
  s.x_min = s.cx - 0.5 * s.size;
  s.x_max = s.cx + 0.5 * s.size;
  s.y_min = s.cy - 0.5 * s.size;
  s.y_max = s.cy + 0.5 * s.size;
}

ShapeEstimate* Track::ownShape() {
  if (Tentative* t = tentative()) return &t->shape;
  if (Stale* s = stale()) return &s->shape;
  return nullptr;
}

const ShapeEstimate* Track::ownShape() const {
  return const_cast<Track*>(this)->ownShape();
}

bool passesFilters(const Track& tr, const ShapeEstimate& shape, const ObjectOptions& options,
                   int support) {
  // A thin row of cells along a wall is the wall seen at a grazing angle (or off by
  // localisation), not an object: no cylinder or person shows a straight row that long.
  const bool wall_row =
      tr.hugs_wall && shape.thickness < options.thin_width && shape.length >= options.thin_length;
  return !wall_row && static_cast<int>(tr.cells.size()) + support >= options.min_cells &&
         shape.size >= options.min_size && shape.size <= options.max_size;
}

}  // namespace dynamap
