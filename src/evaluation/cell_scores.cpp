#include "dynamap/evaluation/evaluation.h"
// The cell level of the evaluation: the truth rasterised onto the map's grid and the static
// and dynamic maps scored against it.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace dynamap {
namespace {

// Cell borders computed as x_min + i·res carry rounding error; a wall lying exactly on a border
// must touch the cells on both sides of it, whatever that rounding did.
constexpr double kBorderEps = 1e-9;

double percent(std::size_t part, std::size_t whole) {
  return whole == 0 ? kNaN : 100.0 * static_cast<double>(part) / static_cast<double>(whole);
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

}  // namespace dynamap
