// The Mapper holds D while the scans disagree with S (DynamicMapOptions::d_hold_share): the
// walls of a scan laid at the wrong pose never become objects, and an object that fills a scan
// alone still does.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../test_util.h"
#include "dynamap/people/person_detector.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;

constexpr int kBeams = 361;
constexpr double kAperture = 2 * M_PI * 360.0 / 361.0;  // all round, no beam twice

// The robot at the centre of a 14 x 14 m hall, turning on the spot: S holds the hall free.
void mapTheHall(Mapper& mapper, std::size_t& index) {
  for (int k = 0; k < 30; ++k, ++index) {
    ScanRecord rec;
    rec.index = index;
    rec.t = 0.2 * static_cast<double>(index);
    rec.pose = CPose2D(0, 0, 0.1 * k);
    rec.scan = test::makeScan(test::roomRanges(-7, 7, -7, 7, rec.pose, kBeams, kAperture),
                              kAperture, rec.t);
    mapper.process(rec);
  }
}

// Scans of a 4 x 3 m room around the robot, then of a 5 x 2.5 m one, laid at the hall's
// centre: a pose that is off (a drifting log, a loop not closed), every wall landing where S
// holds free space. The object cells of D after the first room's scans and at the end, and
// after how many scans D was held (-1: never).
struct Held {
  std::size_t first_room = 0, at_end = 0;
  int scans_before_hold = -1;
};
Held scansFromElsewhere(const MapConfig& config) {
  Mapper mapper(config);
  std::size_t index = 0;
  mapTheHall(mapper, index);
  Held h;
  for (int k = 0; k < 30; ++k, ++index) {
    ScanRecord rec;
    rec.index = index;
    rec.t = 0.2 * static_cast<double>(index);
    rec.pose = CPose2D(0, 0, 0.3);
    const std::vector<float> r = k < 15
                                     ? test::roomRanges(-2, 2, -1.5, 1.5, rec.pose, kBeams, kAperture)
                                     : test::roomRanges(-2.5, 2.5, -1.25, 1.25, rec.pose, kBeams,
                                                        kAperture);
    rec.scan = test::makeScan(r, kAperture, rec.t);
    mapper.process(rec);
    if (mapper.map().dynamicHeld() && h.scans_before_hold < 0) h.scans_before_hold = k;
    if (k == 14) h.first_room = mapper.map().countCells().dynamic_occupied;
  }
  h.at_end = mapper.map().countCells().dynamic_occupied;
  return h;
}

TEST(PoseCheck, OnceTheScansDisagreeWithSDHoldsStill) {
  MapConfig config;
  for (const bool people : {true, false}) {  // the share is worked out without people too
    config.people.enabled = people;
    const Held h = scansFromElsewhere(config);
    // The share is averaged over about five scans: it passes 0.8 at the eighth (1 - 0.8^8);
    // by then the first room's walls have crossed D (five hits). The second room's never do,
    // and its beams, crossing the first room's, fade some of those.
    EXPECT_EQ(h.scans_before_hold, 7) << people;
    EXPECT_EQ(h.first_room, 272u) << people;
    EXPECT_EQ(h.at_end, 178u) << people;
  }
  config.map.d_hold_share = 1;  // never held: D takes the second room's walls in too
  const Held never = scansFromElsewhere(config);
  EXPECT_EQ(never.scans_before_hold, -1);
  EXPECT_EQ(never.first_room, 272u);
  EXPECT_GT(never.at_end, 272u + 100u);
}

// Ranges from (0, 0, phi) over `aperture` to a disc of radius r at (cx, cy), else the hall.
std::vector<float> discRanges(double phi, double aperture, int n, double cx, double cy, double r) {
  std::vector<float> out = test::roomRanges(-7, 7, -7, 7, CPose2D(0, 0, phi), n, aperture);
  for (int i = 0; i < n; ++i) {
    const double a = phi - 0.5 * aperture + aperture * i / (n - 1);
    const double along = cx * std::cos(a) + cy * std::sin(a);
    const double off2 = cx * cx + cy * cy - along * along;
    if (along > 0 && off2 < r * r) out[i] = static_cast<float>(along - std::sqrt(r * r - off2));
  }
  return out;
}

TEST(PoseCheck, AnObjectThatFillsTheScanAloneIsStillFound) {
  const MapConfig config;
  Mapper mapper(config);
  std::size_t index = 0;
  mapTheHall(mapper, index);
  // A 0.5 m cylinder 1 m ahead; the scan's 20 degrees all end on it: every hit lands where S
  // holds free space, but on no surface wider than an object.
  constexpr double kNarrow = 20 * M_PI / 180;
  for (int k = 0; k < 30; ++k, ++index) {
    ScanRecord rec;
    rec.index = index;
    rec.t = 0.2 * static_cast<double>(index);
    rec.pose = CPose2D(0, 0, 0);
    rec.scan = test::makeScan(discRanges(0, kNarrow, 21, 1.25, 0, 0.25), kNarrow, rec.t);
    mapper.process(rec);
  }
  EXPECT_FALSE(mapper.map().dynamicHeld());
  EXPECT_GT(mapper.map().countCells().dynamic_occupied, 0u);
  ASSERT_EQ(mapper.tracker().objects().size(), 1u);
  EXPECT_NEAR(mapper.tracker().objects()[0].shape.cx, 1.25, 0.1);
}

TEST(PoseCheck, FreeSurfaceShareCountsOnlyHitsOnSurfacesWiderThanTheLength) {
  const MapConfig config;
  Mapper mapper(config);
  std::size_t index = 0;
  mapTheHall(mapper, index);
  ScanHits hits;
  hits.sensor_x = 0;
  hits.sensor_y = 0;
  hits.step = 0.01;
  for (int i = 0; i < 40; ++i) hits.points.push_back({2.0, -1.0 + 0.05 * i, std::size_t(i)});  // 2 m
  for (int i = 0; i < 10; ++i) hits.points.push_back({-2.0, 0.03 * i, std::size_t(100 + i)});  // 0.3 m
  const PeopleOptions o;
  const std::vector<HitPoint2> free = freeSpaceHits(mapper.map(), hits, o.wall_guard_cells);
  EXPECT_EQ(free.size(), hits.points.size());  // all in the hall's free space
  EXPECT_NEAR(freeSurfaceShare(free, hits, o, 1.2), 40.0 / 50.0, 1e-12);
  EXPECT_NEAR(freeSurfaceShare(free, hits, o, 2.5), 0.0, 1e-12);
  EXPECT_NEAR(shareOfHits(10, hits), 0.2, 1e-12);
}

}  // namespace
}  // namespace dynamap
