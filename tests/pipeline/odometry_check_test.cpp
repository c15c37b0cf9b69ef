// OdometryCheck (keep_better_odometry): which of the odometry and slam's poses pass 2 maps on.

#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.h"
#include "dynamap/pipeline/slam_run.h"

namespace dynamap {
namespace {

/// 120 scans of a 10 x 4 m room from a robot driving along it and back, at the true poses.
std::vector<ScanRecord> roomDrive() {
  std::vector<ScanRecord> recs;
  for (std::size_t i = 0; i < 120; ++i) {
    const double s = i < 60 ? 0.1 * double(i) : 0.1 * double(119 - i);
    const mrpt::poses::CPose2D pose(-3 + s, 0.2 * std::sin(0.3 * double(i)), 0.05 * std::cos(0.2 * double(i)));
    ScanRecord r;
    r.index = i;
    r.t = 1000 + 0.2 * double(i);
    r.pose = pose;
    r.scan = test::makeScan(test::roomRanges(-5, 5, -2, 2, pose, 181, M_PI), M_PI, r.t);
    recs.push_back(r);
  }
  return recs;
}

/// OdometryCheck::add of `rec` with its scan worked out as pass 1 does (default insertion).
void addTo(OdometryCheck& check, const ScanRecord& rec) {
  const InsertionOptions ins;
  check.add(rec, makeRangeData(*rec.scan, ins.max_distance_insertion,
                               ins.horizontal_tolerance_deg * M_PI / 180.0));
}

/// The poses of `recs`, the second half of them moved by (dx, 0): a map doubled by drift.
std::vector<mrpt::poses::CPose2D> drifted(const std::vector<ScanRecord>& recs, double dx) {
  std::vector<mrpt::poses::CPose2D> poses;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const mrpt::poses::CPose2D& p = recs[i].pose;
    poses.emplace_back(p.x() + (i >= 60 ? dx : 0), p.y(), p.phi());
  }
  return poses;
}

TEST(OdometryCheck, KeepsTheOdometryWhenItLaysTheScansBetter) {
  const auto recs = roomDrive();
  OdometryCheck check;
  for (const auto& r : recs) addTo(check, r);
  SlamRun run;
  run.poses = drifted(recs, 0.08);
  check.decide(run);
  EXPECT_TRUE(run.checked);
  EXPECT_FALSE(run.layout_full);
  EXPECT_TRUE(run.kept_odometry);
  EXPECT_EQ(run.odometry_consistency.scans, 120u);
  EXPECT_LT(run.odometry_consistency.global_m + 0.01, run.slam_consistency.global_m);
  for (std::size_t i = 0; i < recs.size(); ++i) EXPECT_EQ(run.poses[i], recs[i].pose) << i;
}

TEST(OdometryCheck, KeepsSlamsPosesWhenTheOdometryDrifted) {
  auto recs = roomDrive();
  const auto truth = drifted(recs, 0.0);
  const auto odometry = drifted(recs, 0.08);
  for (std::size_t i = 0; i < recs.size(); ++i) recs[i].pose = odometry[i];
  OdometryCheck check;
  for (const auto& r : recs) addTo(check, r);
  SlamRun run;
  run.poses = truth;
  check.decide(run);
  EXPECT_TRUE(run.checked);
  EXPECT_FALSE(run.kept_odometry);
  EXPECT_EQ(run.poses, truth);
}

TEST(OdometryCheck, MakesNoCheckPastItsBoundOrWithoutOnePosePerScan) {
  const auto recs = roomDrive();
  // 181 beams, every 3rd hit kept: 61 points a scan, so 100 scans' worth is kept, not 120.
  OdometryCheck bounded(6100);
  for (const auto& r : recs) addTo(bounded, r);
  SlamRun run;
  run.poses = drifted(recs, 0.08);
  const auto slam = run.poses;
  bounded.decide(run);
  EXPECT_TRUE(run.layout_full);
  EXPECT_FALSE(run.checked);
  EXPECT_FALSE(run.kept_odometry);
  EXPECT_EQ(run.poses, slam);

  OdometryCheck check;
  for (const auto& r : recs) addTo(check, r);
  SlamRun short_run;  // pass 1 returned fewer poses than scans added: nothing to compare
  short_run.poses.assign(slam.begin(), slam.begin() + 100);
  check.decide(short_run);
  EXPECT_FALSE(short_run.checked);
  EXPECT_EQ(short_run.poses.size(), 100u);

  // 20 scans: none has a partner more than 50 scans away, every distance is the cap for both
  // trajectories, and a tie keeps slam's poses.
  OdometryCheck few;
  for (std::size_t i = 0; i < 20; ++i) addTo(few, recs[i]);
  SlamRun tiny;
  tiny.poses.assign(slam.begin(), slam.begin() + 20);
  tiny.poses[5] = mrpt::poses::CPose2D(9, 9, 1);  // differs from the odometry
  few.decide(tiny);
  EXPECT_TRUE(tiny.checked);
  EXPECT_DOUBLE_EQ(tiny.odometry_consistency.global_m, 0.2);
  EXPECT_DOUBLE_EQ(tiny.slam_consistency.global_m, 0.2);
  EXPECT_FALSE(tiny.kept_odometry);
  EXPECT_EQ(tiny.poses[5], mrpt::poses::CPose2D(9, 9, 1));
}

}  // namespace
}  // namespace dynamap
