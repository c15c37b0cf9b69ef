// The pose graph (MRPT's sparse LM behind PoseGraph), its gate on loop closures, the likelihood
// field's branch and bound (one pose, every place near the best), and Slam on synthetic rooms.

#include <gtest/gtest.h>

#include <cmath>

#include <mrpt/math/wrap2pi.h>

#include "../test_util.h"
#include "dynamap/base/ini.h"
#include "dynamap/localization/field_matcher.h"
#include "dynamap/localization/pose_graph.h"
#include "dynamap/localization/slam.h"

namespace dynamap {
namespace {

using mrpt::poses::CPose2D;

Eigen::Matrix3d info(double sigma_xy, double sigma_phi) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  m(0, 0) = m(1, 1) = 1 / (sigma_xy * sigma_xy);
  m(2, 2) = 1 / (sigma_phi * sigma_phi);
  return m;
}

// A square of side 2 m driven once round: four exact edges, starting estimates off by
// decimetres. The optimum is the square itself.
TEST(PoseGraph, ATinyKnownGraphConvergesToItsExactPoses) {
  PoseGraph g;
  const CPose2D truth[] = {{0, 0, 0}, {2, 0, M_PI / 2}, {2, 2, M_PI}, {0, 2, -M_PI / 2}};
  g.addNode(truth[0]);
  g.addNode({2.3, 0.2, 1.4});
  g.addNode({2.2, 2.4, 3.0});
  g.addNode({-0.3, 2.1, -1.4});
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    g.addEdge({std::size_t(i), std::size_t(j), truth[j] - truth[i], info(0.05, 0.02),
               EdgeKind::Odometry});
  }
  const OptimiseReport r = g.optimise(100, 16.0, 3);
  ASSERT_TRUE(r.converged);
  EXPECT_GT(r.iterations, 0u);
  EXPECT_GT(r.initial_error, 1.0);
  EXPECT_LT(r.final_error, 1e-9);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(g.pose(i).x(), truth[i].x(), 1e-5) << i;
    EXPECT_NEAR(g.pose(i).y(), truth[i].y(), 1e-5) << i;
    EXPECT_NEAR(std::remainder(g.pose(i).phi() - truth[i].phi(), 2 * M_PI), 0.0, 1e-6) << i;
  }
}

// A straight corridor: 21 nodes 1 m apart, chained by scan-match edges, and two edges of a
// search (`kind`) from node 0: one that agrees, and one that says node 20 lies 2 m back (a
// symmetric corridor's look-alike, or a place the building changed at). The gate switches the
// second off and the chain keeps its poses.
void expectTheFalseSearchEdgeRejected(EdgeKind kind) {
  PoseGraph g;
  for (int i = 0; i <= 20; ++i) g.addNode({double(i), 0, 0});
  for (std::size_t i = 0; i < 20; ++i) {
    g.addEdge({i, i + 1, {1, 0, 0}, info(0.02, 0.005), EdgeKind::ScanMatch});
  }
  g.addEdge({0, 10, {10, 0, 0}, info(0.05, 0.02), kind});
  g.addEdge({0, 20, {18, 0, 0}, info(0.05, 0.02), kind});
  const OptimiseReport r = g.optimise(100, 16.0, 3);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.rejected, 1u);
  EXPECT_TRUE(g.edges()[20].active);
  EXPECT_FALSE(g.edges()[21].active);
  for (int i = 0; i <= 20; ++i) EXPECT_NEAR(g.pose(i).x(), i, 1e-6) << i;
}

TEST(PoseGraph, AFalseLoopClosureIsRejectedAndDoesNotBendTheChain) {
  expectTheFalseSearchEdgeRejected(EdgeKind::LoopClosure);
}

// The same corridor tied to a prior map: ties are gated as loop closures are.
TEST(PoseGraph, AFalseTieToAPriorMapIsRejectedLikeALoopClosure) {
  expectTheFalseSearchEdgeRejected(EdgeKind::PriorMap);
}

// A chain of 6 nodes 1 m apart and a loop closure from node 5 back to node 1: node 0 lies 1 m
// from node 5 through the graph (across the closure), node 3 2 m; a closure the gate has
// switched off is no short cut.
TEST(PoseGraph, ThePathThroughTheGraphCrossesActiveLoopClosuresOnly) {
  PoseGraph g;
  std::vector<double> path;
  for (int i = 0; i <= 5; ++i) g.addNode({double(i), 0, 0}), path.push_back(i);
  for (std::size_t i = 0; i < 5; ++i) {
    g.addEdge({i, i + 1, {1, 0, 0}, info(0.02, 0.005), EdgeKind::Odometry});
  }
  g.addEdge({1, 5, {0, 0, 0}, info(0.05, 0.02), EdgeKind::LoopClosure});
  const std::vector<double> d = g.pathThroughLoops(path, 5);
  ASSERT_EQ(d.size(), 6u);
  EXPECT_DOUBLE_EQ(d[5], 0.0);
  EXPECT_DOUBLE_EQ(d[1], 0.0);
  EXPECT_DOUBLE_EQ(d[0], 1.0);
  EXPECT_DOUBLE_EQ(d[3], 2.0);
  EXPECT_DOUBLE_EQ(d[4], 1.0);
  PoseGraph chain;
  for (int i = 0; i <= 5; ++i) chain.addNode({double(i), 0, 0});
  for (std::size_t i = 0; i < 5; ++i) {
    chain.addEdge({i, i + 1, {1, 0, 0}, info(0.02, 0.005), EdgeKind::Odometry});
  }
  PoseEdge off{0, 5, {0, 0, 0}, info(0.05, 0.02), EdgeKind::LoopClosure};
  off.active = false;
  chain.addEdge(off);
  EXPECT_DOUBLE_EQ(chain.pathThroughLoops(path, 5)[0], 5.0);
  EXPECT_THROW(chain.pathThroughLoops(path, 6), std::out_of_range);
  EXPECT_THROW(chain.pathThroughLoops({0, 1}, 0), std::out_of_range);
}

// Too few iterations to converge: the poses stay as they were, and the report says so.
TEST(PoseGraph, AnOptimisationThatDoesNotConvergeKeepsThePoses) {
  PoseGraph g;
  g.addNode({0, 0, 0});
  g.addNode({5, 3, 1});
  g.addEdge({0, 1, {1, 0, 0}, info(0.01, 0.01), EdgeKind::Odometry});
  const OptimiseReport r = g.optimise(1, 16.0, 1);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(g.pose(1).x(), 5.0);
  EXPECT_EQ(g.pose(1).y(), 3.0);
}

TEST(PoseGraph, AnEdgeToAnUnknownNodeIsAnError) {
  PoseGraph g;
  g.addNode({0, 0, 0});
  EXPECT_THROW(g.addEdge({0, 1, {1, 0, 0}, info(1, 1), EdgeKind::Odometry}), std::out_of_range);
}

// A 7 x 4.5 m room seen whole from `at`: its likelihood field, and every `stride`-th hit of
// the scan in the robot's frame.
struct SeenRoom {
  LikelihoodField field;
  std::vector<mrpt::math::TPoint2D> pts;
};
SeenRoom seenRoom(const CPose2D& at, std::size_t stride) {
  mrpt::maps::COccupancyGridMap2D grid(-6, 6, -6, 6, 0.05f);
  const auto scan = test::makeScan(test::roomRanges(-3, 4, -2, 2.5, at, 361, 2 * M_PI * 359 / 360),
                                   2 * M_PI * 359 / 360);
  grid.insertObservation(*scan, mrpt::poses::CPose3D(at));
  return {LikelihoodField::fromGrid(grid, 0.65, 0.05),
          hitPoints(makeRangeData(*scan, 30, 0.01), stride)};
}

// A room's likelihood field: the wide search finds a pose 0.6 m and 4 degrees off its guess.
TEST(FieldMatcher, BranchAndBoundFindsAKnownOffset) {
  const CPose2D at(0.5, -0.3, 0.2);
  const auto [field, pts] = seenRoom(at, 2);
  const CPose2D guess(at.x() - 0.6, at.y() + 0.25, at.phi() - 4 * M_PI / 180);
  const FieldMatch m =
      searchWide(field, pts, guess, 1.0, 10 * M_PI / 180, 0.5 * M_PI / 180, 0.4, 0.9);
  EXPECT_GT(m.score, 0.9);
  EXPECT_NEAR(m.pose.x(), at.x(), 0.03);
  EXPECT_NEAR(m.pose.y(), at.y(), 0.03);
  EXPECT_NEAR(m.pose.phi(), at.phi(), 0.5 * M_PI / 180);
}

// Both coarse levels hold, at every block (those overhanging the field's edges too), the
// largest value of its cells: exactly, for the branch and bound's bounds are these.
TEST(FieldMatcher, EachCoarseLevelIsTheLargestValueOfItsBlock) {
  mrpt::maps::COccupancyGridMap2D grid(-3, 3, -3, 3, 0.05f);
  const CPose2D at(0.2, 0.1, 0.4);
  const auto scan = test::makeScan(test::roomRanges(-2, 2.2, -1.5, 1.8, at, 181, M_PI), M_PI);
  grid.insertObservation(*scan, mrpt::poses::CPose3D(at));
  const LikelihoodField field = LikelihoodField::fromGrid(grid, 0.65, 0.05);
  const auto blockMax = [&](int x0, int y0, int side) {
    double m = 0;
    for (int y = y0; y < y0 + side; ++y) {
      for (int x = x0; x < x0 + side; ++x) m = std::max(m, field.cell(x, y));
    }
    return m;
  };
  const int w = field.cellX(3.5), h = field.cellY(3.5);  // beyond the field on both axes
  int checked = 0, nonzero = 0;
  for (int y = -LikelihoodField::kCoarser - 2; y < h; y += 3) {
    for (int x = -LikelihoodField::kCoarser - 2; x < w; x += 3) {
      ASSERT_EQ(field.coarseUnits(x, y) * LikelihoodField::kUnit,
                blockMax(x, y, LikelihoodField::kCoarse))
          << x << "," << y;
      ASSERT_EQ(field.coarserUnits(x, y) * LikelihoodField::kUnit,
                blockMax(x, y, LikelihoodField::kCoarser))
          << x << "," << y;
      ++checked;
      nonzero += field.coarserUnits(x, y) > 0;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(nonzero, checked / 4);
}

// The branch and bound prunes nothing it should not: its best is the best of every pose of
// the window, scored one by one.
TEST(FieldMatcher, BranchAndBoundFindsTheBestOfAnExhaustiveSearch) {
  const CPose2D at(0.5, -0.3, 0.2);
  const auto [field, pts] = seenRoom(at, 6);
  const CPose2D guess(at.x() - 0.45, at.y() + 0.3, at.phi() - 2 * M_PI / 180);
  const double step = 1.0 * M_PI / 180, window = 0.9;
  const FieldMatch m = searchWide(field, pts, guess, window, 3 * step, step, 0.4, 1.0);
  const int shift = static_cast<int>(std::floor(window / 0.05 + 1e-9));
  double best = 0;
  for (int t = -3; t <= 3; ++t) {
    const CPose2D p(guess.x(), guess.y(), guess.phi() + t * step);
    for (int dy = -shift; dy <= shift; ++dy) {
      for (int dx = -shift; dx <= shift; ++dx) {
        double s = 0;
        for (const auto& q : pts) {
          const mrpt::math::TPoint2D g = p + q;
          s += field.cell(field.cellX(g.x) + dx, field.cellY(g.y) + dy);
        }
        best = std::max(best, s / static_cast<double>(pts.size()));
      }
    }
  }
  EXPECT_GT(best, 0.8);
  EXPECT_DOUBLE_EQ(m.score, best);
}

// A room symmetric under a half turn: its scan fits where it was taken and at the image of that
// place; searchPlaces names both, best first as searchWide's best and runner-up, and no place
// twice.
TEST(FieldMatcher, EveryPlaceNearTheBestIsFoundOnce) {
  mrpt::maps::COccupancyGridMap2D grid(-6, 6, -6, 6, 0.05f);
  const CPose2D at(1.0, 0.5, 0.3), image(-1.0, -0.5, 0.3 - M_PI);
  const auto scan = test::makeScan(test::roomRanges(-3, 3, -2, 2, at, 361, 2 * M_PI * 359 / 360),
                                   2 * M_PI * 359 / 360);
  grid.insertObservation(*scan, mrpt::poses::CPose3D(at));
  const LikelihoodField field = LikelihoodField::fromGrid(grid, 0.65, 0.05);
  const auto pts = hitPoints(makeRangeData(*scan, 30, 0.01), 2);
  const CPose2D centre(0, 0, 0.3);
  const double step = 2 * M_PI / 180;
  const std::vector<FieldMatch> places =
      searchPlaces(field, pts, centre, 2.0, M_PI, step, 1.0, 0.9, 8);
  ASSERT_GE(places.size(), 2u);
  const auto near = [](const CPose2D& a, const CPose2D& b) {
    return std::hypot(a.x() - b.x(), a.y() - b.y()) < 0.1 &&
           std::abs(mrpt::math::wrapToPi(a.phi() - b.phi())) < 3 * M_PI / 180;
  };
  EXPECT_TRUE((near(places[0].pose, at) && near(places[1].pose, image)) ||
              (near(places[0].pose, image) && near(places[1].pose, at)));
  for (std::size_t i = 0; i < places.size(); ++i) {
    EXPECT_GE(places[i].score, 0.9 * places[0].score);
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_FALSE(std::hypot(places[i].pose.x() - places[j].pose.x(),
                              places[i].pose.y() - places[j].pose.y()) <= 1.0 &&
                   std::abs(mrpt::math::wrapToPi(places[i].pose.phi() - places[j].pose.phi())) <=
                       5 * M_PI / 180);
    }
  }
  const FieldMatch wide = searchWide(field, pts, centre, 2.0, M_PI, step, 1.0, 0.9);
  EXPECT_EQ(wide.pose, places[0].pose);
  EXPECT_EQ(wide.runner_up_pose, places[1].pose);
  EXPECT_EQ(wide.runner_up, places[1].score);
}

TEST(SlamOptions, BadValuesAreErrorsNamingTheKey) {
  try {
    SlamOptions o;
    o.load(IniFile::fromText("[slam]\nloop_min_score = 2\n", "x.ini"));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("x.ini: [slam] loop_min_score"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(SlamOptions().load(IniFile::fromText("[slam]\nno_such_key = 1\n", "x.ini")),
               ConfigError);
  EXPECT_THROW(SlamOptions().load(IniFile::fromText("[slam]\nsubmap_max_scans = 1\n", "x.ini")),
               ConfigError);
  // A tie's window may not be capped below where every window starts.
  try {
    SlamOptions().load(IniFile::fromText("[slam]\ntie_max_window_m = 0.1\n", "x.ini"));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[slam] tie_max_window_m"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dynamap
