#include "dynamap/pipeline/robot_path.h"

#include <algorithm>
#include <cmath>

namespace dynamap {

RobotPath::RobotPath(double resolution) : step_(std::max(0.05, resolution)) {}

void RobotPath::add(double x, double y) {
  if (!points_.empty() && std::hypot(x - points_.back().x, y - points_.back().y) < step_) return;
  points_.push_back({x, y});
  // Hours of driving must not grow memory without bound: past kMaxPoints, every other point goes
  // and the step doubles (at 5 cm, the first halving comes after 3.3 km).
  if (points_.size() > kMaxPoints) {
    std::size_t kept = 0;
    for (std::size_t i = 0; i < points_.size(); i += 2) points_[kept++] = points_[i];
    points_.resize(kept);
    step_ *= 2;
  }
}

}  // namespace dynamap
