// PoseTrack: poses looked up by time — interpolation, the heading's wrap, gaps and the ends.

#include "dynamap/base/pose_track.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;
using Lookup = PoseTrack::Lookup;

TEST(PoseTrack, InterpolatesPositionAndHeadingBetweenTheSamplesAround) {
  PoseTrack track;
  track.add(10.0, CPose2D(0, 0, 0.1));
  track.add(11.0, CPose2D(2, -4, 0.5));
  CPose2D p;
  ASSERT_EQ(track.at(10.25, p, false), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.x(), 0.5);
  EXPECT_DOUBLE_EQ(p.y(), -1.0);
  EXPECT_NEAR(p.phi(), 0.2, 1e-12);
  ASSERT_EQ(track.at(11.0, p, false), Lookup::kFound);  // a sample's own time: the sample
  EXPECT_DOUBLE_EQ(p.x(), 2.0);
}

TEST(PoseTrack, TheHeadingTurnsTheShortWayAcrossPi) {
  PoseTrack track;
  track.add(0.0, CPose2D(0, 0, M_PI - 0.1));
  track.add(1.0, CPose2D(0, 0, -M_PI + 0.1));
  CPose2D p;
  ASSERT_EQ(track.at(0.5, p, false), Lookup::kFound);
  EXPECT_NEAR(std::abs(p.phi()), M_PI, 1e-9);  // through pi, not through 0
  ASSERT_EQ(track.at(0.75, p, false), Lookup::kFound);
  EXPECT_NEAR(p.phi(), -M_PI + 0.05, 1e-9);
}

TEST(PoseTrack, NoPoseAcrossAGapWiderThanTheLimit) {
  PoseTrackOptions options;
  options.max_gap = 2.0;
  PoseTrack track(options);
  track.add(0.0, CPose2D(0, 0, 0));
  track.add(2.5, CPose2D(1, 0, 0));
  CPose2D p;
  EXPECT_EQ(track.at(1.0, p, false), Lookup::kMissing);
  EXPECT_DOUBLE_EQ(track.maxGap(), 2.0);
}

// The automatic limit follows the track's own spacing: 3 x the median gap, never under 2 s.
TEST(PoseTrack, TheAutomaticGapLimitFollowsTheSpacing) {
  PoseTrack sparse;  // a pose every 4 s (a log of scans 3-5 s apart)
  for (int k = 0; k <= 10; ++k) sparse.add(4.0 * k + (k == 5 ? 1.0 : 0.0), CPose2D(k, 0, 0));
  EXPECT_DOUBLE_EQ(sparse.maxGap(), 12.0);
  CPose2D p;
  ASSERT_EQ(sparse.at(2.0, p, false), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.x(), 0.5);
  PoseTrack dense;  // 10 Hz: the floor of 2 s
  for (int k = 0; k <= 20; ++k) dense.add(0.1 * k, CPose2D(k, 0, 0));
  EXPECT_DOUBLE_EQ(dense.maxGap(), PoseTrack::kMinAutoGap);
  dense.add(10.0, CPose2D(100, 0, 0));
  EXPECT_EQ(dense.at(5.0, p, false), Lookup::kMissing);
}

// A time off its sample by a rounding error (a printed %.6f against MRPT's 100 ns clock) is that
// sample, even where the samples around are further apart than the gap limit.
TEST(PoseTrack, ATimeWithinTheToleranceOfASampleIsThatSample) {
  PoseTrackOptions options;
  options.max_gap = 2.0;
  PoseTrack track(options);
  track.add(100.0, CPose2D(0, 0, 0));
  track.add(104.000000, CPose2D(4, 0, 0));
  track.add(108.0, CPose2D(8, 0, 0));
  CPose2D p;
  ASSERT_EQ(track.at(104.0000004, p, false), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.x(), 4.0);
  ASSERT_EQ(track.at(103.9999996, p, false), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.x(), 4.0);
  EXPECT_EQ(track.at(103.99, p, false), Lookup::kMissing);  // beyond the tolerance: a gap
}

// Timestamps that repeat (all 0) with different poses: time cannot pick one.
TEST(PoseTrack, DifferentPosesSharingATimeAreAmbiguousWhenAsked) {
  PoseTrackOptions strict;
  strict.shared_time_ambiguous = true;
  PoseTrack track(strict), odometry;
  for (int k = 0; k < 5; ++k) {
    track.add(0.0, CPose2D(k, 0, 0));
    odometry.add(0.0, CPose2D(k, 0, 0));
  }
  CPose2D p;
  EXPECT_EQ(track.at(0.0, p, true), Lookup::kAmbiguous);
  ASSERT_EQ(odometry.at(0.0, p, true), Lookup::kFound);  // not asked: the first one added
  EXPECT_DOUBLE_EQ(p.x(), 0.0);
  PoseTrack same(strict);  // the same pose twice is no ambiguity
  same.add(1.0, CPose2D(1, 2, 0));
  same.add(1.0, CPose2D(1, 2, 0));
  ASSERT_EQ(same.at(1.0, p, true), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.y(), 2.0);
}

TEST(PoseTrack, TheEndsTakeTheNearestSampleOnlyWithinTheirTolerance) {
  PoseTrack track;
  track.add(5.0, CPose2D(1, 2, 0));
  CPose2D p;
  EXPECT_EQ(track.at(5.05, p, false), Lookup::kLater);  // a later sample may still come
  ASSERT_EQ(track.at(5.05, p, true), Lookup::kFound);   // none will: the last one
  EXPECT_DOUBLE_EQ(p.x(), 1.0);
  EXPECT_EQ(track.at(5.0 + PoseTrackOptions().end_tolerance + 0.05, p, true), Lookup::kMissing);
  ASSERT_EQ(track.at(4.95, p, false), Lookup::kFound);  // just before the first
  EXPECT_EQ(track.at(5.0 - PoseTrackOptions().end_tolerance - 0.05, p, false), Lookup::kMissing);
}

TEST(PoseTrack, LateSamplesAreSortedInAndOldOnesForgotten) {
  PoseTrack track;
  track.add(0.0, CPose2D(0, 0, 0));
  track.add(2.0, CPose2D(2, 0, 0));
  track.add(1.0, CPose2D(10, 0, 0));  // out of order: inserted in its place
  CPose2D p;
  ASSERT_EQ(track.at(0.5, p, false), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.x(), 5.0);
  track.forgetBefore(1.5);  // keeps the last sample at or before 1.5
  EXPECT_EQ(track.size(), 2u);
  ASSERT_EQ(track.at(1.5, p, false), Lookup::kFound);
  EXPECT_DOUBLE_EQ(p.x(), 6.0);
}

}  // namespace
}  // namespace dynamap
