#pragma once
// Implementation of fillPolygon (a template: included by polygon_fill.h).

#include <algorithm>
#include <cmath>

namespace dynamap {

/// Sorts a row's crossings ascending: a row has a few (two for a convex stretch), where an
/// insertion sort beats std::sort's set-up; equal values are interchangeable.
inline void sortCrossings(double* first, double* last) {
  if (last - first > 16) {
    std::sort(first, last);
    return;
  }
  for (double* i = first + 1; i < last; ++i) {
    const double v = *i;
    double* j = i;
    for (; j > first && *(j - 1) > v; --j) *j = *(j - 1);
    *j = v;
  }
}

template <typename Span>
void fillPolygon(const std::vector<GridPoint>& vertices, int size_x, int size_y,
                 PolygonFillScratch& scratch, Span&& span) {
  const std::size_t n = vertices.size();
  if (n < 3 || size_x <= 0 || size_y <= 0) return;
  double v_min = vertices[0].v, v_max = vertices[0].v;
  for (const auto& p : vertices) {
    v_min = std::min(v_min, p.v);
    v_max = std::max(v_max, p.v);
  }
  // Rows whose centre v = cy + 0.5 lies in [v_min, v_max).
  const int row_lo = std::max(0, static_cast<int>(std::ceil(v_min - 0.5)));
  const int row_hi = std::min(size_y - 1, static_cast<int>(std::ceil(v_max - 0.5)) - 1);
  if (row_lo > row_hi) return;
  const int rows = row_hi - row_lo + 1;

  // Rows an edge crosses: centres in [min(v0, v1), max(v0, v1)), clipped to the rows above.
  auto rowRange = [&](const GridPoint& a, const GridPoint& b, int& lo, int& hi) {
    const double lo_v = std::min(a.v, b.v), hi_v = std::max(a.v, b.v);
    lo = std::max(row_lo, static_cast<int>(std::ceil(lo_v - 0.5)));
    hi = std::min(row_hi, static_cast<int>(std::ceil(hi_v - 0.5)) - 1);
  };

  // Pass 1: crossings per row; pass 2: their u, bucketed by row (a counting sort).
  auto& count = scratch.row_count;
  count.assign(static_cast<std::size_t>(rows) + 1, 0);
  for (std::size_t k = 0; k < n; ++k) {
    int lo, hi;
    rowRange(vertices[k], vertices[(k + 1) % n], lo, hi);
    for (int r = lo; r <= hi; ++r) ++count[r - row_lo + 1];
  }
  for (int r = 0; r < rows; ++r) count[r + 1] += count[r];
  auto& xs = scratch.crossings;
  xs.resize(count[rows]);
  for (std::size_t k = 0; k < n; ++k) {
    const GridPoint& a = vertices[k];
    const GridPoint& b = vertices[(k + 1) % n];
    int lo, hi;
    rowRange(a, b, lo, hi);
    if (lo > hi) continue;
    const double slope = (b.u - a.u) / (b.v - a.v);
    for (int r = lo; r <= hi; ++r) xs[count[r - row_lo]++] = a.u + (r + 0.5 - a.v) * slope;
  }
  // count[r] now ends row r's slice; rebuild its start from the previous row's end.
  std::uint32_t begin = 0;
  for (int r = 0; r < rows; ++r) {
    const std::uint32_t end = count[r];
    sortCrossings(xs.data() + begin, xs.data() + end);
    for (std::uint32_t k = begin; k + 1 < end; k += 2) {
      // Centres cx + 0.5 within [xs[k], xs[k + 1]).
      const int cx_begin = std::max(0, static_cast<int>(std::ceil(xs[k] - 0.5)));
      const int cx_end = std::min(size_x, static_cast<int>(std::ceil(xs[k + 1] - 0.5)));
      if (cx_begin < cx_end) span(row_lo + r, cx_begin, cx_end);
    }
    begin = end;
  }
}

}  // namespace dynamap
