// Scan-to-scan matching: a scan aligned to the one before it with its far returns, and slam's
// use of it where the submap match fails; how slam's front end weighs its matches.

#include "dynamap/localization/scan_to_scan.h"

#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include "../test_util.h"
#include "dynamap/localization/slam.h"
#include "dynamap/sim/world.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;

constexpr double kDeg = M_PI / 180.0;
constexpr int kBeams = 361;
constexpr double kAperture = M_PI;  // 180 degrees in half-degree steps, as a SICK LMS
constexpr double kMaxRange = 80.0;
constexpr double kInsertion = 8.0;  // every wall below lies beyond it: no hits at all

/// Open ground: four buildings and a long wall at an angle, none nearer than 10 m to the path
/// of headingErrorAfterOpenGround.
sim::StaticWorld campus() {
  sim::StaticWorld w;
  auto box = [&](double x0, double y0, double x1, double y1) {
    w.segments.push_back({{x0, y0}, {x1, y0}});
    w.segments.push_back({{x1, y0}, {x1, y1}});
    w.segments.push_back({{x1, y1}, {x0, y1}});
    w.segments.push_back({{x0, y1}, {x0, y0}});
  };
  box(25, -35, 45, -13);
  box(30, 13, 38, 40);
  box(-20, 22, 5, 35);
  box(-30, -40, -12, -18);
  w.segments.push_back({{60, -25}, {66, 18}});  // a long wall at an angle
  return w;
}

/// Two long parallel walls 3 m apart along x: nothing fixes a position along them.
sim::StaticWorld corridor() {
  sim::StaticWorld w;
  w.segments.push_back({{-200, -1.5}, {200, -1.5}});
  w.segments.push_back({{-200, 1.5}, {200, 1.5}});
  return w;
}

RangeData scanFrom(const sim::StaticWorld& world, const CPose2D& pose) {
  std::vector<float> ranges(kBeams, static_cast<float>(kMaxRange));
  for (int i = 0; i < kBeams; ++i) {
    const double a = -kAperture / 2 + i * kAperture / (kBeams - 1);
    const sim::RayHit h = sim::castRay(world, {}, {pose.x(), pose.y()}, pose.phi() + a, kMaxRange);
    if (h.hit() && h.range < kMaxRange) ranges[i] = static_cast<float>(h.range);
  }
  const auto scan = test::makeScan(ranges, kAperture, 0.0, static_cast<float>(kMaxRange));
  return makeRangeData(*scan, kInsertion, 0.05 * kDeg);
}

double headingError(const CPose2D& a, const CPose2D& b) {
  return std::abs(mrpt::math::wrapToPi(a.phi() - b.phi()));
}

TEST(ScanToScan, FarReturnsOnlyFixTheTurnAndTheStep) {
  const auto world = campus();
  const CPose2D a(0, 0, 0.2), b(1.0, 0.15, 0.2 + 4 * kDeg);
  const ScanReturns earlier = ScanReturns::of(scanFrom(world, a));
  const ScanReturns later = ScanReturns::of(scanFrom(world, b));
  ASSERT_GT(later.returns, 100u);
  const CPose2D truth = b - a;
  // Odometry a degree and 6 cm off, as a metre of drifting wheel odometry can be.
  for (const CPose2D& off : {CPose2D(0.05, -0.03, 1.0 * kDeg), CPose2D(-0.04, 0.02, -0.8 * kDeg)}) {
    SCOPED_TRACE(off.asString());
    const ScanToScanResult r = matchScans(earlier, later, truth + off, ScanToScanLimits{});
    ASSERT_TRUE(r.matched) << r.rejected;
    EXPECT_EQ(r.rejected, nullptr);
    EXPECT_LT(std::hypot(r.increment.x() - truth.x(), r.increment.y() - truth.y()), 0.01);
    EXPECT_LT(headingError(r.increment, truth), 0.02 * kDeg);
    EXPECT_EQ(r.degenerate_directions, 0);
    EXPECT_GT(r.inliers, later.returns * 9 / 10);
  }
}

TEST(ScanToScan, AlongAStraightCorridorTheGuessIsKeptAlongIt) {
  const auto world = corridor();
  const CPose2D a(0, 0, 0), b(1.0, 0.1, 1 * kDeg);
  const ScanReturns earlier = ScanReturns::of(scanFrom(world, a));
  const ScanReturns later = ScanReturns::of(scanFrom(world, b));
  const CPose2D truth = b - a, guess = truth + CPose2D(0.2, 0.05, 0.5 * kDeg);
  const ScanToScanResult r = matchScans(earlier, later, guess, ScanToScanLimits{});
  ASSERT_TRUE(r.matched);
  EXPECT_EQ(r.degenerate_directions, 1);
  EXPECT_NEAR(r.increment.x(), guess.x(), 0.02);  // along: odometry's
  EXPECT_NEAR(r.increment.y(), truth.y(), 0.01);  // across and the heading: the walls'
  EXPECT_LT(headingError(r.increment, truth), 0.05 * kDeg);
}

TEST(ScanToScan, NothingInCommonKeepsTheGuess) {
  const ScanReturns earlier = ScanReturns::of(scanFrom(campus(), CPose2D(0, 0, 0)));
  const ScanReturns none = ScanReturns::of(scanFrom(sim::StaticWorld{}, CPose2D(0, 0, 0)));
  EXPECT_EQ(none.returns, 0u);
  const CPose2D guess(1, 0, 0);
  // Nothing to align; or nothing in the earlier scan for the later one's points to pair with.
  for (const auto& [e, l, why] : {std::tuple{&earlier, &none, "too few returns"},
                                  std::tuple{&none, &earlier, "too few inliers"}}) {
    const ScanToScanResult r = matchScans(*e, *l, guess, ScanToScanLimits{});
    EXPECT_FALSE(r.matched);
    EXPECT_STREQ(r.rejected, why);
    EXPECT_EQ(r.increment, guess);
  }
  // Facing away: the later scan sees the buildings the earlier one had behind it.
  const ScanReturns behind = ScanReturns::of(scanFrom(campus(), CPose2D(0, 0, M_PI)));
  const ScanToScanResult r = matchScans(earlier, behind, CPose2D(0, 0, 0), ScanToScanLimits{});
  EXPECT_FALSE(r.matched);
  EXPECT_STREQ(r.rejected, "too few inliers");
}

/// Slam's heading error [deg] at the end of `steps` from `truth`, each scan seen in `world`,
/// odometry measuring step k as `measured(k, step)`; `placed`: the scans matched to the one
/// before.
template <class Measured>
double headingErrorAtTheEnd(const SlamOptions& o, const sim::StaticWorld& world, CPose2D truth,
                            const std::vector<CPose2D>& steps, Measured measured,
                            std::size_t& placed) {
  InsertionOptions insertion;
  insertion.max_distance_insertion = kInsertion;
  Slam slam(o, ScanMatchOptions{}, DynamicMapOptions{}, insertion);
  CPose2D odometry = truth;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    slam.add(odometry, scanFrom(world, truth));
    truth = truth + steps[k];
    odometry = odometry + measured(k, steps[k]);
  }
  slam.add(odometry, scanFrom(world, truth));
  slam.finish();
  placed = slam.stats().scan_to_scan;
  return headingError(slam.poses().back(), truth) / kDeg;
}

/// The front end's heading after driving 30 m through open ground on odometry whose heading
/// drifts 0.3 degrees per metre, with scan_to_scan on or off.
double headingErrorAfterOpenGround(bool scan_to_scan, std::size_t& placed) {
  SlamOptions o;
  o.scan_to_scan = scan_to_scan;
  std::vector<CPose2D> steps;
  for (int k = 0; k < 30; ++k) steps.emplace_back(1.0, 0.0, k % 10 < 5 ? 2 * kDeg : -2 * kDeg);
  const auto drift = [](std::size_t, const CPose2D& step) {
    return step + CPose2D(0, 0, 0.3 * kDeg);
  };
  return headingErrorAtTheEnd(o, campus(), CPose2D(-5, -2, 0.1), steps, drift, placed);
}

TEST(ScanToScan, SlamHoldsTheHeadingInTheOpenWhereTheSubmapHasNothing) {
  std::size_t on = 0, off = 0;
  const double with = headingErrorAfterOpenGround(true, on);
  const double without = headingErrorAfterOpenGround(false, off);
  EXPECT_EQ(on, 30u);  // every scan after the first: the submaps hold no wall
  EXPECT_EQ(off, 0u);
  EXPECT_NEAR(without, 9.0, 0.5);  // odometry's 0.3 degrees per metre
  EXPECT_LT(with, 0.1);
}

/// A 10 x 7 m room with a pillar off its middle: every wall within the insertion range.
sim::StaticWorld room() {
  sim::StaticWorld w;
  const std::vector<std::pair<double, double>> c = {{-4, -3}, {6, -3}, {6, 4}, {-4, 4}};
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto& a = c[k];
    const auto& b = c[(k + 1) % c.size()];
    w.segments.push_back({{a.first, a.second}, {b.first, b.second}});
  }
  w.segments.push_back({{2, 1}, {3, 1}});
  w.segments.push_back({{3, 1}, {3, 1.6}});
  return w;
}

/// The front end's heading after turning once round on the spot in 30-degree steps that
/// odometry measures 20 % short (6 degrees a step: past the submap match's search and its
/// largest correction), with the matched turn in the guess (guess_sigma_deg > 0) or not.
double headingErrorAfterTurningOnTheSpot(double guess_sigma_deg) {
  SlamOptions o;
  o.scan_to_scan_guess_sigma_deg = guess_sigma_deg;
  const std::vector<CPose2D> steps(12, CPose2D(0, 0, 30 * kDeg));
  const auto short_turn = [](std::size_t, const CPose2D& step) {
    return CPose2D(0, 0, 0.8 * step.phi());
  };
  std::size_t placed = 0;
  return headingErrorAtTheEnd(o, room(), CPose2D(0, 0, 0), steps, short_turn, placed);
}

TEST(ScanToScan, TheMatchedTurnSharpensTheSubmapMatchsGuess) {
  EXPECT_LT(headingErrorAfterTurningOnTheSpot(0.4), 0.2);
  // Alone, each step's 6 degrees is too far for the submap match and for the fallback's
  // scan-to-scan limits: odometry's error stays.
  EXPECT_GT(headingErrorAfterTurningOnTheSpot(0.0), 30.0);
}

/// The scan-match edges of slam driving 3 m through room() on exact odometry.
std::vector<PoseEdge> scanMatchEdges(int match_full_inliers) {
  SlamOptions o;
  o.match_full_inliers = match_full_inliers;
  InsertionOptions insertion;
  insertion.max_distance_insertion = kInsertion;
  Slam slam(o, ScanMatchOptions{}, DynamicMapOptions{}, insertion);
  for (int k = 0; k <= 10; ++k) {
    const CPose2D pose(-2 + 0.3 * k, -1, 0.2);
    slam.add(pose, scanFrom(room(), pose));
  }
  std::vector<PoseEdge> out;
  for (const PoseEdge& e : slam.graph().edges()) {
    if (e.kind == EdgeKind::ScanMatch) out.push_back(e);
  }
  return out;
}

TEST(SlamMatchEdges, AMatchOfFewInliersWeighsInProportionToThem) {
  const double full_xy = 1 / (0.02 * 0.02), full_phi = 1 / std::pow(0.5 * kDeg, 2);
  const auto alike = scanMatchEdges(0);
  ASSERT_GE(alike.size(), 5u);
  for (const PoseEdge& e : alike) {
    EXPECT_DOUBLE_EQ(e.information(0, 0), full_xy);
    EXPECT_DOUBLE_EQ(e.information(2, 2), full_phi);
  }
  // Every match has fewer than 100,000 inliers: each edge's information is inliers / 100,000 of
  // the full one, in translation and heading alike.
  const auto weighed = scanMatchEdges(100000);
  ASSERT_EQ(weighed.size(), alike.size());
  for (const PoseEdge& e : weighed) {
    const double inliers = e.information(0, 0) / full_xy * 100000;
    EXPECT_NEAR(inliers, std::round(inliers), 1e-6);
    EXPECT_GE(inliers, 20.0);  // ScanMatchOptions::min_scan_points
    EXPECT_LE(inliers, 361.0);
    EXPECT_NEAR(e.information(2, 2) / full_phi * 100000, inliers, 1e-6);
  }
}

}  // namespace
}  // namespace dynamap
