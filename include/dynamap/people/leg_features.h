#pragma once
// The shape of a cluster of a scan's points, as numbers a leg classifier can learn from: how many
// points, how wide, how straight, how round, how far from the sensor, and whether its neighbours
// in the scan hide part of it. The features need no map: they are worked out from the scan's own
// points, so a person is recognised where the robot has never been before, and a wall that a pose
// error has moved is still a straight line, never a leg.
//
// Pure functions over ScanHits (person_detector.h), tested without I/O. The same features are
// computed when training the classifier (dynamap train-legs) and when mapping.

#include <array>
#include <cstddef>
#include <vector>

#include "dynamap/people/person_detector.h"

namespace dynamap {

/// The hits of a scan given as ROS gives it (beam i along angle_min + i * increment [rad] in the
/// sensor's frame, a range outside [range_min, range_max) or not finite is no echo), with the
/// sensor at the origin looking along x: the training bags' scans, which have no pose.
ScanHits polarScanHits(double angle_min, double increment, const std::vector<float>& ranges,
                       double range_min, double range_max);

/// A run [begin, end) of ScanHits::points: neighbouring beams (at most max_gap beams without a
/// hit between two of its points), each point within `jump` of the one before.
struct Segment {
  std::size_t begin = 0, end = 0;
  std::size_t size() const { return end - begin; }
};

/// Points of a leg's cluster lie at most this far apart [m], in training and detection alike
/// (the classifier learnt the clusters this cut gives).
constexpr double kLegSegmentJump = 0.13;
/// A cluster of fewer points is never classified.
constexpr std::size_t kLegMinPoints = 3;

/// Splits the hit points of a scan into segments; segments of fewer than min_points are dropped.
std::vector<Segment> segmentScan(const ScanHits& hits, double jump, std::size_t min_points,
                                 std::size_t max_gap = 2);

/// The number of features legFeatures computes.
constexpr std::size_t kLegFeatureCount = 17;
using LegFeatures = std::array<float, kLegFeatureCount>;

/// The names of the features, in order (for reports and the model file's header).
const std::array<const char*, kLegFeatureCount>& legFeatureNames();

/// The features of segment `s` of `hits` (at least 3 points): 0 points, 1 spread (standard
/// deviation about the mean) [m], 2 mean distance to the median point [m], 3 width (first to
/// last point) [m], 4 linearity (mean squared distance to the best line) [m^2], 5 circularity
/// (mean squared distance to the best circle) [m^2], 6 that circle's radius, at most 2 [m],
/// 7 boundary length [m], 8 boundary regularity (standard deviation of the steps) [m], 9 mean
/// curvature [1/m], 10 mean turn between consecutive steps [rad], 11 and 12 mean and standard
/// deviation of the angle each inner point makes with the two ends [rad], 13 distance of the
/// median point from the sensor [m], 14 the beams' spacing at that distance [m], 15 and 16
/// whether the beam before the first point / after the last one ends nearer the sensor (1)
/// or not (0): part of the body may be hidden behind something.
LegFeatures legFeatures(const ScanHits& hits, const Segment& s);

}  // namespace dynamap
