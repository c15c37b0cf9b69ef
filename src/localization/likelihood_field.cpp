#include "dynamap/localization/likelihood_field.h"

#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>

namespace dynamap {

std::vector<mrpt::math::TPoint2D> hitPoints(const RangeData& rd, std::size_t stride) {
  std::vector<mrpt::math::TPoint2D> pts;
  const mrpt::poses::CPose2D sensor = rd.mount2D();
  stride = std::max<std::size_t>(stride, 1);
  for (std::size_t i = 0; i < rd.size(); i += stride) {
    if (rd.kinds[i] != BeamKind::Hit) continue;
    const double r = rd.ranges[i];
    pts.push_back(sensor + mrpt::math::TPoint2D(r * rd.cos_angle[i], r * rd.sin_angle[i]));
  }
  return pts;
}

LikelihoodField LikelihoodField::fromGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                          double occupied_threshold, double sigma_m) {
  LikelihoodField f;
  f.res_ = grid.getResolution();
  const int gw = static_cast<int>(grid.getSizeX()), gh = static_cast<int>(grid.getSizeY());
  // getCell() is P(free): occupied above the threshold <=> the raw cell below this value.
  using Grid = mrpt::maps::COccupancyGridMap2D;
  const int occupied_below = Grid::p2l(static_cast<float>(1.0 - occupied_threshold));
  const auto& raw = grid.getRawMap();
  std::vector<std::pair<int, int>> occupied;
  int x0 = gw, x1 = -1, y0 = gh, y1 = -1;
  for (int cy = 0; cy < gh; ++cy) {
    for (int cx = 0; cx < gw; ++cx) {
      if (raw[static_cast<std::size_t>(cy) * gw + cx] >= occupied_below) continue;
      occupied.emplace_back(cx, cy);
      x0 = std::min(x0, cx), x1 = std::max(x1, cx), y0 = std::min(y0, cy), y1 = std::max(y1, cy);
    }
  }
  if (occupied.empty()) return f;
  const int reach = std::max(1, static_cast<int>(std::ceil(3.0 * sigma_m / f.res_)));
  x0 -= reach, y0 -= reach, x1 += reach, y1 += reach;
  f.w_ = x1 - x0 + 1, f.h_ = y1 - y0 + 1;
  f.x0_ = grid.idx2x(0) + x0 * f.res_, f.y0_ = grid.idx2y(0) + y0 * f.res_;
  // Cells the grid has never observed are kUnknown; observed free cells 0.
  f.fine_.assign(static_cast<std::size_t>(f.w_) * f.h_, kUnknown);
  for (int cy = 0; cy < f.h_; ++cy) {
    for (int cx = 0; cx < f.w_; ++cx) {
      const int gx = cx + x0, gy = cy + y0;
      if (gx < 0 || gy < 0 || gx >= gw || gy >= gh) continue;
      if (raw[static_cast<std::size_t>(gy) * gw + gx] != 0) f.fine_[cx + cy * f.w_] = 0;
    }
  }
  // One kernel, stamped (by max) around every occupied cell: exact within the reach.
  std::vector<std::uint8_t> kernel;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const double d2 = (dx * dx + dy * dy) * f.res_ * f.res_;
      kernel.push_back(
          static_cast<std::uint8_t>(std::lround(kMax * std::exp(-0.5 * d2 / (sigma_m * sigma_m)))));
    }
  }
  const int side = 2 * reach + 1;
  for (const auto& [ox, oy] : occupied) {
    const int cx = ox - x0, cy = oy - y0;
    for (int dy = -reach; dy <= reach; ++dy) {
      std::uint8_t* row = &f.fine_[static_cast<std::size_t>(cy + dy) * f.w_ + cx];
      const std::uint8_t* k = &kernel[static_cast<std::size_t>(dy + reach) * side + reach];
      for (int dx = -reach; dx <= reach; ++dx) {
        row[dx] = row[dx] == kUnknown ? k[dx] : std::max(row[dx], k[dx]);
      }
    }
  }
  f.buildCoarse();
  f.buildCoarser();
  return f;
}

namespace {

// The level above `src` (sw x sh bytes): (sw + lag) x (sh + lag) bytes, at (i, j) the largest of
// src at (i - lag + a * step, j - lag + b * step) for a, b in [0, n); a cell off `src` or
// `unknown` counts as 0, the maximum's start. Along x, then along y: each row is copied framed
// by zeros (unknown made 0), so the loops run without a check per cell and vectorise.
std::vector<std::uint8_t> blockMaxima(const std::vector<std::uint8_t>& src, int sw, int sh, int n,
                                      int step, int lag, std::uint8_t unknown) {
  const int dw = sw + lag, dh = sh + lag;
  std::vector<std::uint8_t> along_x(static_cast<std::size_t>(dw) * sh, 0);
  std::vector<std::uint8_t> row(static_cast<std::size_t>(dw + (n - 1) * step), 0);
  for (int y = 0; y < sh; ++y) {
    const std::uint8_t* in = &src[static_cast<std::size_t>(y) * sw];
    for (int x = 0; x < sw; ++x) row[lag + x] = in[x] == unknown ? 0 : in[x];
    std::uint8_t* out = &along_x[static_cast<std::size_t>(y) * dw];
    for (int a = 0; a < n; ++a) {
      const std::uint8_t* shifted = &row[static_cast<std::size_t>(a) * step];
      for (int i = 0; i < dw; ++i) out[i] = std::max(out[i], shifted[i]);
    }
  }
  std::vector<std::uint8_t> dst(static_cast<std::size_t>(dw) * dh, 0);
  for (int j = 0; j < dh; ++j) {
    std::uint8_t* out = &dst[static_cast<std::size_t>(j) * dw];
    for (int b = 0; b < n; ++b) {
      const int y = j - lag + b * step;
      if (y < 0 || y >= sh) continue;
      const std::uint8_t* in = &along_x[static_cast<std::size_t>(y) * dw];
      for (int i = 0; i < dw; ++i) out[i] = std::max(out[i], in[i]);
    }
  }
  return dst;
}

}  // namespace

void LikelihoodField::buildCoarse() {
  // coarse_ (i, j) is the block starting at fine cell (i - kCoarse, j - kCoarse): the fine cells
  // i - kCoarse ... i - 1 (and so along y), unknown ones 0.
  coarse_ = blockMaxima(fine_, w_, h_, kCoarse, 1, kCoarse, kUnknown);
}

void LikelihoodField::buildCoarser() {
  // coarser_ (i, j) is the block starting at fine cell (i - kCoarser, j - kCoarser): the coarse
  // blocks starting there and every kCoarse cells on, coarse_ index i - (kCoarser - kCoarse) +
  // a kCoarse. coarse_ holds no unknown byte (its values are at most kMax).
  static_assert(kCoarser % kCoarse == 0, "a coarser block is whole coarse blocks");
  coarser_ = blockMaxima(coarse_, w_ + kCoarse, h_ + kCoarse, kCoarser / kCoarse, kCoarse,
                         kCoarser - kCoarse, kUnknown);
}

int LikelihoodField::cellX(double x) const {
  return static_cast<int>(std::floor((x - x0_) / res_ + 0.5));
}

int LikelihoodField::cellY(double y) const {
  return static_cast<int>(std::floor((y - y0_) / res_ + 0.5));
}

double LikelihoodField::interpolate(double x, double y, double& gx, double& gy) const {
  const double u = (x - x0_) / res_, v = (y - y0_) / res_;
  const double fu = std::floor(u), fv = std::floor(v);
  const int i = static_cast<int>(fu), j = static_cast<int>(fv);
  const double a = u - fu, b = v - fv;
  const double v00 = cell(i, j), v10 = cell(i + 1, j), v01 = cell(i, j + 1),
               v11 = cell(i + 1, j + 1);
  gx = ((1 - b) * (v10 - v00) + b * (v11 - v01)) / res_;
  gy = ((1 - a) * (v01 - v00) + a * (v11 - v10)) / res_;
  return (1 - a) * (1 - b) * v00 + a * (1 - b) * v10 + (1 - a) * b * v01 + a * b * v11;
}

}  // namespace dynamap
