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

void LikelihoodField::buildCoarse() {
  // Sliding maximum over kCoarse cells, along x, then along y. Index (i, j) of coarse_ is the
  // block starting at fine cell (i - kCoarse, j - kCoarse). Unknown cells and cells off the
  // field count as 0, the maximum's start: each row is copied so, framed by kCoarse zeros, and
  // the loops run without a check per cell (the compiler vectorises them).
  const int cw = w_ + kCoarse, ch = h_ + kCoarse;
  std::vector<std::uint8_t> along_x(static_cast<std::size_t>(cw) * h_, 0);
  std::vector<std::uint8_t> row(static_cast<std::size_t>(w_ + 2 * kCoarse), 0);
  for (int y = 0; y < h_; ++y) {
    const std::uint8_t* src = &fine_[static_cast<std::size_t>(y) * w_];
    for (int x = 0; x < w_; ++x) row[kCoarse + x] = src[x] == kUnknown ? 0 : src[x];
    std::uint8_t* out = &along_x[static_cast<std::size_t>(y) * cw];
    for (int k = 0; k < kCoarse; ++k) {
      for (int i = 0; i < cw; ++i) out[i] = std::max(out[i], row[i + k]);
    }
  }
  coarse_.assign(static_cast<std::size_t>(cw) * ch, 0);
  for (int j = 0; j < ch; ++j) {
    std::uint8_t* out = &coarse_[static_cast<std::size_t>(j) * cw];
    for (int y = std::max(0, j - kCoarse); y < std::min(h_, j); ++y) {
      const std::uint8_t* in = &along_x[static_cast<std::size_t>(y) * cw];
      for (int i = 0; i < cw; ++i) out[i] = std::max(out[i], in[i]);
    }
  }
}

void LikelihoodField::buildCoarser() {
  // A coarser block is kCoarser / kCoarse coarse blocks along x, then along y: index (i, j) of
  // coarser_ (the block starting at fine cell (i - kCoarser, j - kCoarser)) takes the coarse
  // blocks starting at (i - kCoarser + a, j - kCoarser + b) for a, b in 0, kCoarse, ...; those
  // starting before coarse_'s first (fine cell -kCoarse) cover no cell of the field: 0. Each
  // coarse row is copied framed by zeros, so the loops run without a check per cell.
  constexpr int kRatio = kCoarser / kCoarse;
  static_assert(kRatio * kCoarse == kCoarser, "a coarser block is whole coarse blocks");
  const int cw = w_ + kCoarse, ch = h_ + kCoarse;    // coarse_
  const int bw = w_ + kCoarser, bh = h_ + kCoarser;  // coarser_
  const int lag = kCoarser - kCoarse;  // coarser_ index i is coarse_ index i - lag
  std::vector<std::uint8_t> along_x(static_cast<std::size_t>(bw) * ch, 0);
  std::vector<std::uint8_t> row(static_cast<std::size_t>(lag + cw + kCoarser), 0);
  for (int j = 0; j < ch; ++j) {
    std::copy_n(&coarse_[static_cast<std::size_t>(j) * cw], cw, row.begin() + lag);
    std::uint8_t* out = &along_x[static_cast<std::size_t>(j) * bw];
    for (int a = 0; a < kRatio; ++a) {
      const std::uint8_t* in = &row[static_cast<std::size_t>(a) * kCoarse];
      for (int i = 0; i < bw; ++i) out[i] = std::max(out[i], in[i]);
    }
  }
  coarser_.assign(static_cast<std::size_t>(bw) * bh, 0);
  for (int j = 0; j < bh; ++j) {
    std::uint8_t* out = &coarser_[static_cast<std::size_t>(j) * bw];
    for (int b = 0; b < kRatio; ++b) {
      const int y = j - lag + b * kCoarse;
      if (y < 0 || y >= ch) continue;
      const std::uint8_t* in = &along_x[static_cast<std::size_t>(y) * bw];
      for (int i = 0; i < bw; ++i) out[i] = std::max(out[i], in[i]);
    }
  }
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
