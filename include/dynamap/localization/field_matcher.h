#pragma once
// Loop-closure matching of a scan against a finished submap's LikelihoodField: an exact search
// over a window of poses (every cell and every angle step) by branch and bound, then
// Levenberg-Marquardt refinement on the interpolated field (Olson's correlative matching,
// Cartographer's two-level precomputation and refinement).
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
  mrpt::poses::CPose2D runner_up_pose;  ///< where runner_up was found
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  ///< J^T J of the points at `pose`
};

/// The best pose within the window, exactly, by branch and bound over the field's coarse level,
/// without a prior. Also finds the best score at least `separation_m` (or 5 deg) away from it,
/// among poses scoring above `ambiguity_ratio` times the best. With `min_score` (a caller that
/// refuses a best below it) the search stops early: a best found below it may be any pose
/// scoring below it, and its runner_up is then not the best of the others.
FieldMatch searchWide(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                      const mrpt::poses::CPose2D& guess, double window_m, double window_rad,
                      double step_rad, double separation_m, double ambiguity_ratio,
                      double min_score = 0);

/// Every distinct place of the same window search scoring at least `ratio` times the best, best
/// first, at most `max_places`: a pose within `separation_m` and 5 degrees of a better one is
/// that one's. Scores as searchWide's; no runner_up.
std::vector<FieldMatch> searchPlaces(const LikelihoodField& field,
                                     const std::vector<mrpt::math::TPoint2D>& pts,
                                     const mrpt::poses::CPose2D& guess, double window_m,
                                     double window_rad, double step_rad, double separation_m,
                                     double ratio, std::size_t max_places);
/// Levenberg-Marquardt on sum (1 - field)^2 over the points plus a prior pulling towards
/// `prior` (weights per metre and per radian; 0: none), from `start`. `information` of the
/// result is the points' J^T J at the end (the prior excluded).
FieldMatch refine(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                  const mrpt::poses::CPose2D& start, const mrpt::poses::CPose2D& prior,
                  double translation_weight, double rotation_weight, int max_iterations);

}  // namespace dynamap
