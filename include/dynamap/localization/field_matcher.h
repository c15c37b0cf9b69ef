#pragma once
// Scan-to-submap matching against a LikelihoodField: a correlative search over a window of
// poses (every cell and every angle step), then Gauss-Newton refinement on the interpolated
// field (Olson's real-time correlative matching followed by Cartographer's refinement).
//
// Poses and points: the pose is the robot's in the field's frame, the points are the scan's end
// points in the robot's frame. Deterministic: ties go to the pose searched first.

#include <mrpt/math/TPoint2D.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <vector>

#include "dynamap/localization/likelihood_field.h"

namespace dynamap {

/// A pose found by a search, and how well the points lie on the field there.
struct FieldMatch {
  mrpt::poses::CPose2D pose;
  double score = 0;  ///< mean field value of the points, in [0, 1]
  /// Of a wide search: the best score found at a pose far from `pose` (0 if none); a ratio to
  /// `score` near 1 means the match is ambiguous (a symmetric corridor).
  double runner_up = 0;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  ///< J^T J of the points at `pose`
};

/// The points of `pts` that fall, seen from `pose`, on cells the field's grid has observed, with
/// observed cells `margin` cells away on each side too. A point beyond what the submap has
/// seen (a wall further along a corridor) has nothing to match, and one near that edge would
/// pull the pose back towards the known end of the wall: a search moving the pose by up to
/// `margin` cells never takes a point kept here into unknown space.
std::vector<mrpt::math::TPoint2D> knownPoints(const LikelihoodField& field,
                                              const std::vector<mrpt::math::TPoint2D>& pts,
                                              const mrpt::poses::CPose2D& pose, int margin);

/// The mean field value of `pts` seen from `pose` (nearest cell).
double fieldScore(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                  const mrpt::poses::CPose2D& pose);

/// The best pose within +-`window_m` (in cells) and +-`window_rad` (in `step_rad` steps) of
/// `guess`, each cell of offset costing `offset_cost` of score per squared metre and each
/// squared radian `turn_cost`: a local search that prefers the guess along flat directions.
FieldMatch searchLocal(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                       const mrpt::poses::CPose2D& guess, double window_m, double window_rad,
                       double step_rad, double offset_cost, double turn_cost);

/// The best pose within the window, exactly, by branch and bound over the field's coarse level,
/// without a prior. Also finds the best score at least `separation_m` (or 5 deg) away from it,
/// among poses scoring above `ambiguity_ratio` times the best.
FieldMatch searchWide(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                      const mrpt::poses::CPose2D& guess, double window_m, double window_rad,
                      double step_rad, double separation_m, double ambiguity_ratio);

/// Levenberg-Marquardt on sum (1 - field)^2 over the points plus a prior pulling towards
/// `prior` (weights per metre and per radian; 0: none), from `start`. `information` of the
/// result is the points' J^T J at the end (the prior excluded).
FieldMatch refine(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                  const mrpt::poses::CPose2D& start, const mrpt::poses::CPose2D& prior,
                  double translation_weight, double rotation_weight, int max_iterations);

}  // namespace dynamap
