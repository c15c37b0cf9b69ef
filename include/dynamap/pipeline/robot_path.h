#pragma once
// The robot's path as the pictures draw it: decimated, and bounded in memory however long the run.

#include <cstddef>
#include <vector>

namespace dynamap {

struct PathPoint {
  double x, y;
};

/// A point every `step` metres (at least 5 cm, the cell size if larger); past kMaxPoints points
/// it is thinned to every other point and the step doubles, so its memory stays bounded.
class RobotPath {
 public:
  static constexpr std::size_t kMaxPoints = 1 << 16;
  explicit RobotPath(double resolution);
  /// Adds the robot's position when it is `step` or more from the last point kept.
  void add(double x, double y);
  const std::vector<PathPoint>& points() const { return points_; }

 private:
  std::vector<PathPoint> points_;
  double step_;
};

}  // namespace dynamap
