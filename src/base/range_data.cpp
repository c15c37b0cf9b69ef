#include "dynamap/base/range_data.h"

#include <mrpt/math/CMatrixFixed.h>

#include <cmath>

namespace dynamap {

mrpt::poses::CPose2D RangeData::sensorIn(const mrpt::poses::CPose3D& robot) const {
  return mrpt::poses::CPose2D(robot + mount);
}

namespace {

BeamKind kindOf(const mrpt::obs::CObservation2DRangeScan& scan, std::size_t i, float range,
                double insertion_range) {
  if (!scan.getScanRangeValidity(i)) return BeamKind::NoEcho;
  if (!std::isfinite(range) || range < 0.0f) return BeamKind::Bad;
  return range < static_cast<float>(insertion_range) ? BeamKind::Hit : BeamKind::Beyond;
}

}  // namespace

RangeData makeRangeData(const mrpt::obs::CObservation2DRangeScan& scan, double insertion_range,
                        double horizontal_tolerance) {
  RangeData rd;
  makeRangeData(scan, insertion_range, horizontal_tolerance, rd);
  return rd;
}

void makeRangeData(const mrpt::obs::CObservation2DRangeScan& scan, double insertion_range,
                   double horizontal_tolerance, RangeData& rd) {
  const std::size_t n = scan.getScanSize();
  const double first_before = rd.first, step_before = rd.step, dir_before = rd.dir;
  rd.mount = scan.sensorPose;
  // The mount's z axis pointing down: the scan plane is seen from below.
  rd.upside_down = scan.sensorPose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>()(2, 2) < 0;
  rd.planar = scan.isPlanarScan(horizontal_tolerance);
  rd.aperture = scan.aperture;
  rd.first = n > 1 ? -0.5 * scan.aperture : 0.0;  // a lone beam looks ahead
  rd.step = n > 1 ? scan.aperture / static_cast<double>(n - 1) : 0.0;
  rd.dir = (scan.rightToLeft ^ rd.upside_down) ? 1.0 : -1.0;
  rd.insertion_range = insertion_range;
  rd.sensor_max_range = scan.maxRange;
  rd.bad_beams = 0;
  rd.ranges.resize(n);
  rd.kinds.resize(n);
  const bool same_beams = rd.cos_angle.size() == n && rd.first == first_before &&
                          rd.step == step_before && rd.dir == dir_before;
  if (!same_beams) {
    rd.cos_angle.resize(n);
    rd.sin_angle.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      rd.cos_angle[i] = std::cos(rd.angle(i));
      rd.sin_angle[i] = std::sin(rd.angle(i));
    }
  }
  if (n == 0) return;
  // getScanRange() returns a reference into MRPT's contiguous array of ranges: read them as
  // one array instead of making an out-of-line, index-checked call per beam.
  const float* ranges = &scan.getScanRange(0);
  for (std::size_t i = 0; i < n; ++i) {
    rd.ranges[i] = ranges[i];
    rd.kinds[i] = kindOf(scan, i, rd.ranges[i], insertion_range);
    if (rd.kinds[i] == BeamKind::Bad) ++rd.bad_beams;
  }
}

}  // namespace dynamap
