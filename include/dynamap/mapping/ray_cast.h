#pragma once
// Ray traversal over grid cells.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

namespace dynamap {

/// Fractional bits of the fixed-point stepping. MRPT uses 9, whose rounding drifts by up to
/// n / 1024 cells on an n-cell ray; 32 bits keep every ray within its end cell at any length.
constexpr int kRayFracBits = 32;

/// Visits the cells a beam crosses going from cell (x0, y0) to cell (x1, y1): exactly
/// n = max(|x1 - x0|, |y1 - y0|) cells, the first being (x0, y0) and never (x1, y1) itself (the
/// end cell is the hit, handled by the caller). Steps one cell along the major axis at a time
/// with fixed-point minor-axis increments (cell i is floor(start + i * d / n) on each axis), the
/// cells MRPT's own insertion frees.
/// `visit(cx, cy)` is called once per cell, in order from the start. No bounds checks: both ends
/// must be inside the grid, and then so is every cell visited.
template <typename Visit>
inline void traceRay(int x0, int y0, int x1, int y1, Visit&& visit) {
  const int dx = x1 - x0;
  const int dy = y1 - y0;
  const int adx = std::abs(dx);
  const int ady = std::abs(dy);
  const int n = adx > ady ? adx : ady;
  if (n == 0) return;
  // Rounded (d << bits) / n; one of the two is exactly +-1 cell.
  const int64_t step_x = (static_cast<int64_t>(dx) * (int64_t{1} << kRayFracBits)) / n;
  const int64_t step_y = (static_cast<int64_t>(dy) * (int64_t{1} << kRayFracBits)) / n;
  int64_t fx = static_cast<int64_t>(x0) << kRayFracBits;
  int64_t fy = static_cast<int64_t>(y0) << kRayFracBits;
  int cx = x0;
  int cy = y0;
  for (int i = 0; i < n; ++i) {
    visit(cx, cy);
    fx += step_x;
    fy += step_y;
    cx = static_cast<int>(fx >> kRayFracBits);
    cy = static_cast<int>(fy >> kRayFracBits);
  }
}

/// traceRay's cells as linear indices x + y * size_x, for a grid `size_x` cells wide: the same
/// cells in the same order, stepping the index itself instead of recomputing it at each cell.
template <typename Visit>
inline void traceRayIndex(int x0, int y0, int x1, int y1, std::size_t size_x, Visit&& visit) {
  const int dx = x1 - x0;
  const int dy = y1 - y0;
  const bool x_major = std::abs(dx) > std::abs(dy);
  const int n = x_major ? std::abs(dx) : std::abs(dy);
  if (n == 0) return;
  // The major axis moves one cell per step; the minor one in traceRay's fixed point, whose
  // integer part changes by at most one cell per step.
  const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(size_x);
  const int d_major = x_major ? dx : dy, d_minor = x_major ? dy : dx;
  const std::ptrdiff_t major_step = (d_major > 0 ? 1 : -1) * (x_major ? 1 : row);
  const std::ptrdiff_t minor_stride = x_major ? row : 1;
  const int64_t step = (static_cast<int64_t>(d_minor) * (int64_t{1} << kRayFracBits)) / n;
  int64_t f = static_cast<int64_t>(x_major ? y0 : x0) << kRayFracBits;
  std::ptrdiff_t idx = x0 + y0 * row;
  for (int i = 0; i < n; ++i) {
    visit(static_cast<std::size_t>(idx));
    const int64_t next = f + step;
    idx += major_step + ((next >> kRayFracBits) - (f >> kRayFracBits)) * minor_stride;
    f = next;
  }
}

/// The cells traceRay visits, as a list (for tests and tools; the mapper uses traceRay).
std::vector<std::pair<int, int>> rayCells(int x0, int y0, int x1, int y1);

}  // namespace dynamap
