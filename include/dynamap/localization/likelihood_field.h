#pragma once
// A likelihood field: for each cell, how close it is to an occupied cell of an occupancy grid,
// exp(-d^2 / 2 sigma^2) with d the distance to the nearest occupied cell, truncated at 3 sigma.
// Scan points are scored against it (the mean value over the points: 1 = every point on a
// wall) and a pose is refined by Gauss-Newton on its bilinear interpolation, which is smooth
// where the raw grid is a step. A second level holds, for each cell, the largest value over the
// block of `kCoarse` x `kCoarse` cells starting there: an upper bound of every pose of that
// block, for a branch and bound search; a third the same over `kCoarser` x `kCoarser` cells
// (Cartographer's precomputation grids, two levels).
//
// Values are kept as bytes (1/254 steps, one more byte value marks cells never observed): a
// finished submap costs three bytes per cell.

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPoint2D.h>

#include <cstdint>
#include <vector>

#include "dynamap/base/range_data.h"

namespace dynamap {

/// The end points of the scan's hits (BeamKind::Hit) in the robot's frame (the mount applied),
/// every `stride`-th beam only.
std::vector<mrpt::math::TPoint2D> hitPoints(const RangeData& rd, std::size_t stride = 1);

class LikelihoodField {
 public:
  static constexpr int kCoarse = 4;    ///< cells per side of a coarse block
  static constexpr int kCoarser = 16;  ///< cells per side of a coarser block (4 coarse ones)
  static constexpr int kMax = 254;     ///< a wall's value in units
  static constexpr double kUnit = 1.0 / kMax;  ///< the step of the field's values

  LikelihoodField() = default;
  /// From the cells of `grid` with P(occ) > `occupied_threshold`, cropped to their bounding box
  /// plus the field's reach. An empty grid gives an empty field (every value 0).
  static LikelihoodField fromGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                  double occupied_threshold, double sigma_m);

  bool empty() const { return w_ == 0; }
  double resolution() const { return res_; }
  /// Cell indices of a point; may be outside [0, w) x [0, h).
  int cellX(double x) const;
  int cellY(double y) const;
  /// The value of a cell in [0, 1]; 0 outside the field and where the grid is unknown.
  double cell(int cx, int cy) const {
    if (cx < 0 || cy < 0 || cx >= w_ || cy >= h_) return 0.0;
    const std::uint8_t v = fine_[cx + cy * w_];
    return v == kUnknown ? 0.0 : v * kUnit;
  }
  /// The largest value over cells [cx, cx + kCoarse) x [cy, cy + kCoarse), in units of kUnit.
  int coarseUnits(int cx, int cy) const { return blockAt(coarse_, kCoarse, cx, cy); }
  /// The largest value over cells [cx, cx + kCoarser) x [cy, cy + kCoarser), in units of kUnit.
  int coarserUnits(int cx, int cy) const { return blockAt(coarser_, kCoarser, cx, cy); }
  /// Bilinear interpolation at (x, y) and its gradient.
  double interpolate(double x, double y, double& gx, double& gy) const;
  std::size_t bytes() const { return fine_.size() + coarse_.size() + coarser_.size(); }

 private:
  void buildCoarse();
  void buildCoarser();
  /// The value in units of the block of `side` cells starting at (cx, cy) in `level` ((w_ +
  /// side) x (h_ + side), offset by side); 0 for a block that covers no cell of the field.
  int blockAt(const std::vector<std::uint8_t>& level, int side, int cx, int cy) const {
    return (cx < -side || cy < -side || cx >= w_ || cy >= h_)
               ? 0
               : level[(cx + side) + (cy + side) * (w_ + side)];
  }
  static constexpr std::uint8_t kUnknown = 255;  // a byte of fine_: never observed

  double res_ = 0.05, x0_ = 0, y0_ = 0;  // (x0_, y0_): the centre of cell (0, 0)
  int w_ = 0, h_ = 0;
  std::vector<std::uint8_t> fine_;     // w_ x h_
  std::vector<std::uint8_t> coarse_;   // (w_ + kCoarse) x (h_ + kCoarse), offset by kCoarse
  std::vector<std::uint8_t> coarser_;  // (w_ + kCoarser) x (h_ + kCoarser), offset by kCoarser
};

}  // namespace dynamap
