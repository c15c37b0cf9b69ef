#pragma once
// Ray traversal over grid cells.

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

/// The cells traceRay visits, as a list (for tests and tools; the mapper uses traceRay).
std::vector<std::pair<int, int>> rayCells(int x0, int y0, int x1, int y1);

}  // namespace dynamap
