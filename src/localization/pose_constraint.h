#pragma once
// A match's correction kept only where the matched points pin the pose down. Private to the
// localization layer (the scan matcher and the scan-to-scan matcher share it).

#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>

namespace dynamap {

/// The derivative of a point's distance along the unit direction `n` with respect to the pose
/// (x, y, heading), for the point at (rx, ry) from the robot, rotated into the map's frame.
inline Eigen::Vector3d poseJacobian(const Eigen::Vector2d& n, double rx, double ry) {
  return {n.x(), n.y(), -n.x() * ry + n.y() * rx};
}

/// `guess` moved by the correction to `matched` only along the directions (x, y, heading) whose
/// eigenvalue of `info_per_point` (the inliers' point-to-line information divided by their
/// number) is at least `min_constraint`; `degenerate` receives how many were not. Along a
/// straight corridor a match's answer is noise, and odometry is better.
mrpt::poses::CPose2D keepConstrained(const mrpt::poses::CPose2D& guess,
                                     const mrpt::poses::CPose2D& matched,
                                     const Eigen::Matrix3d& info_per_point, double min_constraint,
                                     int& degenerate);

}  // namespace dynamap
