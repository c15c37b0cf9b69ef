#include "correlative_search.h"
// The grid search that puts a scan's guess within ICP's reach: a score field over the window
// of S around the guess, searched over headings and offsets. Used by ScanMatcher::match.

#include <algorithm>
#include <cmath>
#include <vector>

#include "dynamap/base/angles.h"

namespace dynamap {
namespace {

constexpr int kReach = 3;  // [cells] a point scores down to 0 this far from an occupied cell

/// The search's scores over a window of the grid: 1 on an occupied cell, falling linearly to 0
/// at kReach cells from one.
struct ScoreField {
  int cx0 = 0, cy0 = 0, w = 0, h = 0;
  std::vector<float> score;
  bool empty() const { return w <= 0 || h <= 0; }
};

/// d = std::min(d, v), written as a branch: along a row each cell waits for the one before it,
/// and std::min's select makes the CPU wait too, while a branch (rarely taken: mostly far from
/// walls the neighbour's value plus a step is no lower) lets it run ahead. The same value.
inline void lowerTo(float& d, float v) {
  if (v < d) d = v;
}

/// Two-pass chamfer distance (1 / 1.4 cells) in place, over a w x h window whose values are at
/// most `cap`. The passes run over a copy framed by a border of `cap`: a border cell's value plus
/// a step exceeds every value, so it never wins, exactly as a neighbour outside the window is
/// skipped. Each row takes its minimum over the row before first (independent cells: the compiler
/// vectorises it), then along itself; a minimum does not depend on the order it is taken in, so
/// every value is the one the textbook cell-by-cell passes give.
void chamfer(std::vector<float>& dist, int w, int h, float cap) {
  const int pw = w + 2;
  std::vector<float> pad(static_cast<std::size_t>(pw) * (h + 2), cap);
  for (int y = 0; y < h; ++y) {
    std::copy_n(dist.begin() + static_cast<std::ptrdiff_t>(y) * w, w,
                pad.begin() + static_cast<std::ptrdiff_t>(y + 1) * pw + 1);
  }
  for (int y = 1; y <= h; ++y) {
    float* d = pad.data() + static_cast<std::ptrdiff_t>(y) * pw;
    const float* up = d - pw;
    for (int x = 1; x <= w; ++x) {
      d[x] = std::min(std::min(d[x], up[x] + 1.0f), std::min(up[x - 1], up[x + 1]) + 1.4f);
    }
    for (int x = 1; x <= w; ++x) lowerTo(d[x], d[x - 1] + 1.0f);
  }
  for (int y = h; y >= 1; --y) {
    float* d = pad.data() + static_cast<std::ptrdiff_t>(y) * pw;
    const float* down = d + pw;
    for (int x = w; x >= 1; --x) {
      d[x] = std::min(std::min(d[x], down[x] + 1.0f), std::min(down[x + 1], down[x - 1]) + 1.4f);
    }
    for (int x = w; x >= 1; --x) lowerTo(d[x], d[x + 1] + 1.0f);
  }
  for (int y = 0; y < h; ++y) {
    std::copy_n(pad.begin() + static_cast<std::ptrdiff_t>(y + 1) * pw + 1, w,
                dist.begin() + static_cast<std::ptrdiff_t>(y) * w);
  }
}

/// The field over every cell the sample's points can reach from `guess` shifted by up to
/// `shift` cells, plus the field's own reach. `occupied` says, for each raw cell value, whether
/// S holds that cell occupied.
ScoreField scoreField(const DynamicGridMap& map, const std::vector<mrpt::math::TPoint2D>& sample,
                      const mrpt::poses::CPose2D& guess, int shift,
                      const OccupiedByRawValue& occupied) {
  double x0 = guess.x(), x1 = x0, y0 = guess.y(), y1 = y0;
  for (const auto& p : sample) {
    const mrpt::math::TPoint2D g = guess + p;
    x0 = std::min(x0, g.x), x1 = std::max(x1, g.x), y0 = std::min(y0, g.y), y1 = std::max(y1, g.y);
  }
  const int sx = static_cast<int>(map.getSizeX()), sy = static_cast<int>(map.getSizeY());
  const int margin = shift + kReach + 2;
  ScoreField f;
  f.cx0 = std::max(0, map.x2idx(x0) - margin);
  f.cy0 = std::max(0, map.y2idx(y0) - margin);
  const int cx1 = std::min(sx - 1, map.x2idx(x1) + margin);
  const int cy1 = std::min(sy - 1, map.y2idx(y1) + margin);
  if (cx1 <= f.cx0 || cy1 <= f.cy0) return f;
  f.w = cx1 - f.cx0 + 1, f.h = cy1 - f.cy0 + 1;
  // Distance (in cells) to the nearest occupied cell, capped at kReach + 1.
  std::vector<float> dist(static_cast<std::size_t>(f.w) * f.h, static_cast<float>(kReach + 1));
  const auto& raw = map.getRawMap();
  for (int y = 0; y < f.h; ++y) {
    const std::size_t row = static_cast<std::size_t>(f.cy0 + y) * static_cast<std::size_t>(sx);
    for (int x = 0; x < f.w; ++x) {
      if (occupied(raw[row + static_cast<std::size_t>(f.cx0 + x)])) dist[x + y * f.w] = 0;
    }
  }
  chamfer(dist, f.w, f.h, static_cast<float>(kReach + 1));
  f.score.resize(dist.size());
  for (std::size_t i = 0; i < dist.size(); ++i) {
    f.score[i] = std::max(0.0f, 1.0f - dist[i] / static_cast<float>(kReach));
  }
  return f;
}

/// The sum of the field's scores under the sample's cells (px, py) moved by (dx, dy), in the
/// sample's order; a cell outside the window scores 0.
double sampleScore(const ScoreField& f, const std::vector<int>& px, const std::vector<int>& py,
                   int dx, int dy) {
  double sc = 0;
  for (std::size_t i = 0; i < px.size(); ++i) {
    const int x = px[i] + dx, y = py[i] + dy;
    if (x >= 0 && y >= 0 && x < f.w && y < f.h) sc += f.score[x + y * f.w];
  }
  return sc;
}

/// sampleScore for every dx in [-shift, shift] at once, into row[dx + shift], when every moved
/// cell lies in the window (`idx`: the cells' indices): no check per point, and each sum adds the
/// same scores in the same order as sampleScore, so it is the same, while the 2 shift + 1 sums
/// run side by side over neighbouring cells instead of one after another.
void sampleRow(const ScoreField& f, const std::vector<int>& idx, int dy, int shift,
               std::vector<double>& row) {
  std::fill(row.begin(), row.end(), 0.0);
  const int n = 2 * shift + 1;
  for (const int i : idx) {
    const float* cells = &f.score[static_cast<std::size_t>(i + dy * f.w - shift)];
    for (int k = 0; k < n; ++k) row[static_cast<std::size_t>(k)] += cells[k];
  }
}

}  // namespace

mrpt::poses::CPose2D correlativeGuess(const DynamicGridMap& map,
                                      const std::vector<mrpt::math::TPoint2D>& pts,
                                      const mrpt::poses::CPose2D& guess, const ScanMatchOptions& o,
                                      const OccupiedByRawValue& occupied) {
  const double res = map.getResolution();
  const int shift = static_cast<int>(std::floor(o.search_xy_m / res + 1e-9));
  const int turns = static_cast<int>(std::floor(o.search_deg / 0.5 + 1e-9));
  if ((shift == 0 && turns == 0) || pts.empty()) return guess;
  std::vector<mrpt::math::TPoint2D> sample;  // up to 120 points, evenly through the scan
  const std::size_t stride = pts.size() / 120 + 1;
  for (std::size_t i = 0; i < pts.size(); i += stride) sample.push_back(pts[i]);
  const ScoreField f = scoreField(map, sample, guess, shift, occupied);
  if (f.empty()) return guess;
  // Odometry drifts little from one scan to the next: each cell of offset costs
  // search_offset_cost points squared, a turn to the search's edge a twentieth of the points.
  const double turn_prior = 0.05 * static_cast<double>(sample.size());
  double best = -1e300;
  int best_t = 0, best_x = 0, best_y = 0;
  std::vector<int> px(sample.size()), py(sample.size()), idx(sample.size());
  std::vector<double> row(static_cast<std::size_t>(2 * shift + 1));
  for (int t = -turns; t <= turns; ++t) {
    const mrpt::poses::CPose2D turned(guess.x(), guess.y(), guess.phi() + t * 0.5 * kDegToRad);
    bool inside = true;
    for (std::size_t i = 0; i < sample.size(); ++i) {
      const mrpt::math::TPoint2D g = turned + sample[i];
      px[i] = map.x2idx(g.x) - f.cx0;
      py[i] = map.y2idx(g.y) - f.cy0;
      idx[i] = px[i] + py[i] * f.w;
      inside =
          inside && px[i] >= shift && py[i] >= shift && px[i] + shift < f.w && py[i] + shift < f.h;
    }
    for (int dy = -shift; dy <= shift; ++dy) {
      if (inside) sampleRow(f, idx, dy, shift, row);
      for (int dx = -shift; dx <= shift; ++dx) {
        double sc =
            inside ? row[static_cast<std::size_t>(dx + shift)] : sampleScore(f, px, py, dx, dy);
        sc -= o.search_offset_cost * (dx * dx + dy * dy) +
              (turns ? turn_prior * (t * t) / double(turns * turns) : 0.0);
        if (sc > best) best = sc, best_t = t, best_x = dx, best_y = dy;
      }
    }
  }
  return {guess.x() + best_x * res, guess.y() + best_y * res,
          guess.phi() + best_t * 0.5 * kDegToRad};
}

}  // namespace dynamap
