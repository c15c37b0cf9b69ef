#include "tf_tree.h"

#include <mrpt/math/TPose2D.h>

#include <cmath>

namespace dynamap::bag {

using mrpt::poses::CPose2D;

std::string frameName(const std::string& f) {
  return !f.empty() && f[0] == '/' ? f.substr(1) : f;
}

double yawOf(const geometry_msgs::Quaternion& q) {
  const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  if (!std::isfinite(n2) || std::abs(n2 - 1.0) > 0.01) return NAN;
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

std::optional<CPose2D> pose2D(double x, double y, const geometry_msgs::Quaternion& q) {
  const double yaw = yawOf(q);
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw)) return std::nullopt;
  // From a TPose2D: CPose2D(x, y, phi) wraps phi again, which moves a yaw atan2 gave by ~1e-17
  // (the CARMEN reader's poses are made the same way: a log's pose crosses a bag unchanged).
  return CPose2D(mrpt::math::TPose2D(x, y, yaw));
}

}  // namespace dynamap::bag
