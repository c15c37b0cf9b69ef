// People found by the shape of their legs: where S has never seen free space, and on a map that
// does not hold still (a moving robot given no poses), where motion says nothing.

#include <gtest/gtest.h>

#include <cmath>

#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/people/leg_classifier.h"
#include "dynamap/people/leg_features.h"
#include "dynamap/people/person_detector.h"
#include "dynamap/people/person_tracker.h"

namespace dynamap {
namespace {

constexpr double kStep = 0.33 * M_PI / 180;
constexpr int kBeams = 361;  // +-60 degrees

double discRange(double a, double cx, double cy, double r) {
  const double b = cx * std::cos(a) + cy * std::sin(a), c = cx * cx + cy * cy - r * r;
  return b * b - c < 0 ? 1e9 : b - std::sqrt(b * b - c);
}

/// A scan from the origin of two 12 cm legs around (x, y), feet `stride` apart across the beams.
ScanHits legsAt(double x, double y, double stride) {
  std::vector<float> r;
  for (int i = 0; i < kBeams; ++i) {
    const double a = -180 * kStep + i * kStep;
    const double d = std::min(discRange(a, x, y - stride / 2, 0.06), discRange(a, x, y + stride / 2, 0.06));
    r.push_back(static_cast<float>(std::min(d, 30.0)));
  }
  return polarScanHits(-180 * kStep, kStep, r, 0.05, 30.0);
}

// Scans of someone walking across the sensor's view 2 m ahead at 1 m/s, 10 scans a second, fed
// to a tracker; the first scan at which a person is reported, or -1.
int firstReportedScan(const LegClassifier* legs, double free_share) {
  const DynamicGridMap map;  // S has seen nothing: no hit is in its free space
  const PeopleOptions o;
  PersonTracker tracker(o);
  for (int k = 0; k < 40; ++k) {
    const ScanHits h = legsAt(2.0, -1.0 + 0.1 * k, k % 4 < 2 ? 0.25 : 0.3);
    tracker.update(detectPeople(map, h, o, legs), h, 0.1 * k, free_share);
    if (!tracker.reported().empty()) return k;
  }
  return -1;
}

TEST(ShapeDetection, APersonWhereSHasSeenNothingIsTrackedFromTheFirstScans) {
  const LegClassifier& legs = LegClassifier::builtin();
  const int k = firstReportedScan(&legs, 0.0);
  EXPECT_GE(k, 0) << "never reported";
  EXPECT_LE(k, PeopleOptions{}.shape_confirm_scans + 2);
  // Without the classifier nothing there is in S's free space: no detection at all.
  EXPECT_EQ(firstReportedScan(nullptr, 0.0), -1);
}

TEST(ShapeDetection, OnAMapThatDoesNotHoldStillOnlyShapeConfirms) {
  const LegClassifier& legs = LegClassifier::builtin();
  // Most hits in S's free space (a moving robot mapped with fixed poses): the legs are still
  // a person by their shape.
  EXPECT_GE(firstReportedScan(&legs, 0.9), 0);
  PersonTracker tracker;
  tracker.update({}, ScanHits{}, 0.0, 0.9);
  EXPECT_FALSE(tracker.mapSteady());
  tracker.update({}, ScanHits{}, 0.1, 0.05);
  EXPECT_FALSE(tracker.mapSteady()) << "one steady scan after a moving one is no steady map";
  for (int k = 2; k < 20; ++k) tracker.update({}, ScanHits{}, 0.1 * k, 0.05);
  EXPECT_TRUE(tracker.mapSteady());
}

TEST(ShapeDetection, AWallSeenAfterAPoseErrorIsNoLeg) {
  // A straight wall 0.5 m long, 2 m ahead, wherever S has it: the classifier never sees a leg in
  // it, so a wall a pose error moved into S's free space makes no shape detection.
  std::vector<float> r;
  for (int i = 0; i < kBeams; ++i) {
    const double a = -180 * kStep + i * kStep, y = 2.0 * std::tan(a);
    r.push_back(static_cast<float>(std::abs(y) <= 0.25 ? 2.0 / std::cos(a) : 30.0));
  }
  const ScanHits h = polarScanHits(-180 * kStep, kStep, r, 0.05, 30.0);
  const DynamicGridMap map;
  EXPECT_TRUE(shapeDetections(map, h, PeopleOptions{}, LegClassifier::builtin()).empty());
}

}  // namespace
}  // namespace dynamap
