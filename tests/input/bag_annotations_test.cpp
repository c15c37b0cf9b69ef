// Annotated bags: leg markers go with the scan recorded after them, a person's ground truth
// with the scan recorded before it, and a message of the wrong size is an error naming it.

#include <gtest/gtest.h>

#include <cmath>

#include "../bag_test_util.h"
#include "dynamap/evaluation/bag_people_truth.h"
#include "dynamap/input/bag_annotations.h"
#include "../test_util.h"

namespace dynamap {
namespace {

test::RosScan scanOf(float range) {
  test::RosScan s;
  s.ranges.assign(5, range);
  return s;
}

TEST(BagAnnotations, LegMarkersGoWithTheNextScan) {
  const std::string path = test::tempDir("legbag") + "/legs.bag";
  {
    test::BagWriter w(path);
    w.poseArray("/leg_cluster_positions", 1.0, {{1.0, 0.5}, {1.2, -0.5}});
    w.scan("/training_scan", 1.01, scanOf(2.0f));
    w.scan("/training_scan", 1.1, scanOf(3.0f));  // the markers still hold
    w.poseArray("/leg_cluster_positions", 1.15, {{2.0, 0.0}});
    w.scan("/training_scan", 1.2, scanOf(4.0f));
    w.close();
  }
  const auto scans = readLegTrainingBag(path, "/training_scan", "/leg_cluster_positions");
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_EQ(scans[0].legs.size(), 2u);
  EXPECT_DOUBLE_EQ(scans[0].legs[1].y, -0.5);
  EXPECT_EQ(scans[1].legs.size(), 2u);
  ASSERT_EQ(scans[2].legs.size(), 1u);
  EXPECT_DOUBLE_EQ(scans[2].legs[0].x, 2.0);
  EXPECT_FLOAT_EQ(scans[2].scan.ranges[0], 4.0f);
  EXPECT_EQ(scans[2].scan.index, 2u);
  // Without a markers topic (a bag of empty rooms) no scan has a leg.
  for (const auto& s : readLegTrainingBag(path, "/training_scan", "")) EXPECT_TRUE(s.legs.empty());
  EXPECT_THROW(readLegTrainingBag(path, "/nothing", ""), std::runtime_error);
}

TEST(BagAnnotations, APersonGoesWithTheScanRecordedBeforeIt) {
  const std::string path = test::tempDir("personbag") + "/people.bag";
  {
    test::BagWriter w(path);
    w.person("/ground_truth_people_tracks", 0.5, 9.0, 9.0, 1);  // before any scan: dropped
    w.scan("/scan", 1.0, scanOf(2.0f));
    w.person("/ground_truth_people_tracks", 1.05, 1.5, 0.25, 2);
    w.scan("/scan", 1.1, scanOf(2.0f));
    w.scan("/scan", 1.2, scanOf(2.0f));
    w.person("/ground_truth_people_tracks", 1.25, -0.5, 2.0, 7);
    w.close();
  }
  const auto truth = readPersonTruthBag(path, "/scan", "/ground_truth_people_tracks");
  ASSERT_EQ(truth.size(), 2u);
  EXPECT_EQ(truth[0].scan_index, 0u);
  EXPECT_EQ(truth[0].id, 2);
  EXPECT_DOUBLE_EQ(truth[0].position.x, 1.5);
  EXPECT_DOUBLE_EQ(truth[0].position.y, 0.25);
  EXPECT_EQ(truth[1].scan_index, 2u);
  EXPECT_EQ(truth[1].id, 7);
  EXPECT_NEAR(truth[1].t, 1.25, 1e-6);
  // The person topic holds leg_tracker/Person: a LaserScan topic in its place is named.
  try {
    readPersonTruthBag(path, "/scan", "/scan");
    FAIL() << "a LaserScan topic was read as people";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("people.bag"), std::string::npos) << e.what();
  }
}

TEST(BagPeopleTruth, EachPersonIsPlacedWithItsScansPoseAndTheLasersMount) {
  const std::string path = test::tempDir("truthbag") + "/people.bag";
  {
    test::BagWriter w(path);
    // The laser 0.2 m ahead of base_link; the Person is in the laser's frame.
    w.tf(0.9, "base_link", "laser", mrpt::poses::CPose2D(0.2, 0, 0), true);
    w.scan("/scan", 1.0, scanOf(2.0f));
    w.person("/ground_truth_people_tracks", 1.05, 1.5, 0.25, 3);
    w.scan("/scan", 2.0, scanOf(2.0f));
    w.person("/ground_truth_people_tracks", 2.05, 1.0, 0.0, 3);
    w.close();
  }
  // The run's poses: the robot at (1, 0) facing +y, then a scan the run has no pose for.
  const std::vector<TimedPose> poses = {{1.0, 1.0, 0.0, M_PI / 2}};
  const BagPeopleTruth t = bagPeopleTruth(path, BagOptions{}, "/ground_truth_people_tracks", poses);
  EXPECT_EQ(t.messages, 2u);
  EXPECT_EQ(t.unplaced, 1u);
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].scan_index, 0u);
  EXPECT_EQ(t.rows[0].id, 3);
  // Laser at (1, 0.2) facing +y: (1.5, 0.25) in its frame is (1 - 0.25, 0.2 + 1.5).
  EXPECT_NEAR(t.rows[0].x, 0.75, 1e-9);
  EXPECT_NEAR(t.rows[0].y, 1.7, 1e-9);
}

}  // namespace
}  // namespace dynamap
