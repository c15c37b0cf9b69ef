#include "bag_messages.h"

#include <cmath>

namespace dynamap::bag {

using mrpt::obs::CObservation2DRangeScan;

CObservation2DRangeScan::Ptr convertScan(const sensor_msgs::LaserScan& m, double& centre,
                                         std::string& bad) {
  const std::size_t n = m.ranges.size();
  if (n == 0) {
    bad = "scan with no beams";
    return nullptr;
  }
  if (n > kMaxBeams) {
    bad = "scan with more than 1,000,000 beams";
    return nullptr;
  }
  const double inc = m.angle_increment, lo = m.range_min, hi = m.range_max;
  if (!std::isfinite(m.angle_min) || !std::isfinite(inc) || (n > 1 && inc == 0) ||
      std::abs(inc) * static_cast<double>(n - 1) > 2 * M_PI + 1e-6) {
    bad = "scan with bad beam angles (angle_min, angle_increment)";
    return nullptr;
  }
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > 0) || lo > hi) {
    bad = "scan with bad range_min / range_max";
    return nullptr;
  }
  // MRPT spreads the beams evenly over `aperture`, symmetric about the sensor's x axis; ROS's
  // beam i lies at angle_min + i * angle_increment, counter-clockwise when the increment is
  // positive.
  centre = m.angle_min + inc * static_cast<double>(n - 1) / 2;
  auto scan = std::make_shared<CObservation2DRangeScan>();
  scan->aperture = static_cast<float>(std::abs(inc) * static_cast<double>(n - 1));
  scan->rightToLeft = inc >= 0;
  scan->maxRange = static_cast<float>(hi);
  scan->sensorLabel = m.header.frame_id.empty() ? "LASER" : m.header.frame_id;
  // In one call: MRPT's per-beam setters are out of line and bounds-checked, a fifth of a
  // ROS 2 bag's reading time.
  static thread_local std::vector<char> valid;
  valid.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = m.ranges[i];
    valid[i] = std::isfinite(r) && r >= lo && r <= hi ? 1 : 0;
  }
  scan->loadFromVectors(n, m.ranges.data(), valid.data());
  return scan;
}

}  // namespace dynamap::bag
