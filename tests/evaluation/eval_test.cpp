// The evaluation's definitions (docs/evaluation.md) on tiny hand-written truth and tracks, SA/DA
// on a hand-made 5 x 5 map, and `dynamap eval` end to end on the bundled tiny scenario.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "../test_util.h"
#include "dynamap/evaluation/evaluation.h"

namespace dynamap {
namespace {

using sim::BodyKind;

// A truth of scans at 1 Hz (scan k at t = k): object 1 (0.3 m) moves from (0, 0) to (5, 0) in
// [2, 3]; object 2 (0.3 m) stands still at (0, 3) all along. Both are seen by 10 beams.
struct Truth {
  std::vector<TruthRow> rows;
  std::vector<TruthMove> moves;
};

Truth twoObjects(std::size_t scans = 20) {
  Truth t;
  for (std::size_t k = 0; k < scans; ++k) {
    const double time = static_cast<double>(k);
    const double x1 = time < 3 ? 0.0 : 5.0;
    t.rows.push_back({k, time, BodyKind::Object, 1, x1, 0.0, 0.3, 10});
    t.rows.push_back({k, time, BodyKind::Object, 2, 0.0, 3.0, 0.3, 10});
  }
  t.moves.push_back({1, 1, 2.0, 3.0, {0, 0}, {5, 0}});
  return t;
}

TrackRow track(std::size_t scan, int id, double x, double y) {
  TrackRow r;
  r.scan_index = scan;
  r.t = static_cast<double>(scan);
  r.object_id = id;
  r.cx = x;
  r.cy = y;
  r.size_m = 0.3;
  return r;
}

/// Id `id` on object 2 at every scan.
void addStill(std::vector<TrackRow>& tracks, int id, std::size_t scans = 20) {
  for (std::size_t k = 0; k < scans; ++k) tracks.push_back(track(k, id, 0.05, 3.0));
}

TEST(EvalObjects, CleanDetectionIsCorrectWithItsLatency) {
  const Truth t = twoObjects();
  std::vector<TrackRow> tracks;
  addStill(tracks, 20);
  for (std::size_t k = 0; k < 3; ++k) tracks.push_back(track(k, 10, 0.1, 0.0));
  for (std::size_t k = 5; k < 20; ++k) tracks.push_back(track(k, 10, 5.1, 0.1));  // 2 s late
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  ASSERT_EQ(s.moves.size(), 1u);
  const MoveResult& m = s.moves[0];
  EXPECT_TRUE(m.visible);
  EXPECT_EQ(m.visible_scan, 3u);  // the first scan at t >= t_end with >= 3 hits
  EXPECT_TRUE(m.correct);
  EXPECT_FALSE(m.sizeError());
  EXPECT_EQ(s.correct, 1u);
  EXPECT_EQ(s.not_detected, 0u);
  EXPECT_EQ(s.size_errors, 0u);
  EXPECT_EQ(s.static_as_objects, 0u);
  EXPECT_DOUBLE_EQ(m.latency_s, 2.0);
  EXPECT_EQ(m.latency_scans, 2u);
  ASSERT_EQ(s.ids.size(), 2u);
  EXPECT_EQ(s.ids[0].track_id, 10);
  EXPECT_EQ(s.ids[0].body, (BodyKey{BodyKind::Object, 1}));
  EXPECT_EQ(s.ids[1].body, (BodyKey{BodyKind::Object, 2}));
}

TEST(EvalObjects, VisibilityWaitsForThreeHits) {
  Truth t = twoObjects();
  for (auto& r : t.rows) {
    if (r.id == 1 && r.scan_index >= 3 && r.scan_index < 6) r.hits = 2;  // seen at scan 6
  }
  const ObjectScores s = evaluateObjects(t.rows, t.moves, {});
  EXPECT_TRUE(s.moves[0].visible);
  EXPECT_EQ(s.moves[0].visible_scan, 6u);
  EXPECT_DOUBLE_EQ(s.moves[0].visible_t, 6.0);
}

TEST(EvalObjects, NeverSeenAtItsNewPlaceIsNotScored) {
  Truth t = twoObjects();
  for (auto& r : t.rows) {
    if (r.id == 1 && r.scan_index >= 3) r.hits = 0;
  }
  const ObjectScores s = evaluateObjects(t.rows, t.moves, {});
  EXPECT_FALSE(s.moves[0].visible);
  EXPECT_EQ(s.visible, 0u);
  EXPECT_EQ(s.not_detected, 0u);
}

TEST(EvalObjects, MissIsNotDetected) {
  const Truth t = twoObjects();
  std::vector<TrackRow> tracks;
  addStill(tracks, 20);
  for (std::size_t k = 0; k < 3; ++k) tracks.push_back(track(k, 10, 0.0, 0.0));
  // Found only after the 10 s window (visible at 3, window to 13; at 1 Hz, 10 scans).
  for (std::size_t k = 14; k < 20; ++k) tracks.push_back(track(k, 10, 5.0, 0.0));
  EvalOptions ten_scans;
  ten_scans.detect_window_scans = 10;
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks, ten_scans);
  EXPECT_FALSE(s.moves[0].matched);
  EXPECT_FALSE(s.moves[0].correct);
  EXPECT_EQ(s.not_detected, 1u);
  EXPECT_EQ(s.correct, 0u);
  EXPECT_EQ(s.latency.count, 0u);
  EXPECT_TRUE(std::isnan(s.latency.median_s));
}

TEST(EvalObjects, MatchRadiusIsTheLargerOfQuarterMetreAndDiameter) {
  TruthRow small{0, 0, BodyKind::Object, 1, 0, 0, 0.1, 5};
  TruthRow big{0, 0, BodyKind::Object, 2, 0, 0, 0.6, 5};
  EXPECT_TRUE(rowMatches(track(0, 1, 0.25, 0), small, {}));
  EXPECT_FALSE(rowMatches(track(0, 1, 0.26, 0), small, {}));
  EXPECT_TRUE(rowMatches(track(0, 1, 0.6, 0), big, {}));
  EXPECT_FALSE(rowMatches(track(0, 1, 0.61, 0), big, {}));
}

TEST(EvalObjects, SwappedIdentityIsASizeError) {
  const Truth t = twoObjects();
  std::vector<TrackRow> tracks;
  addStill(tracks, 20);  // id 20 is object 2's by majority
  for (std::size_t k = 0; k < 3; ++k) tracks.push_back(track(k, 10, 0.0, 0.0));
  // Object 1 at its new place reported under object 2's id for a few scans.
  for (std::size_t k = 4; k < 7; ++k) tracks.push_back(track(k, 20, 5.0, 0.0));
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  const MoveResult& m = s.moves[0];
  EXPECT_TRUE(m.matched);
  EXPECT_FALSE(m.correct);
  EXPECT_TRUE(m.wrong_id);
  EXPECT_TRUE(m.sizeError());
  EXPECT_EQ(s.size_errors, 1u);
  EXPECT_EQ(s.not_detected, 0u);
  EXPECT_EQ(s.correct, 0u);
}

TEST(EvalObjects, DuplicateIdOnOneObjectIsASizeErrorButStillDetected) {
  const Truth t = twoObjects();
  std::vector<TrackRow> tracks;
  addStill(tracks, 20);
  for (std::size_t k = 0; k < 20; ++k) tracks.push_back(track(k, 10, k < 3 ? 0.0 : 5.0, 0.0));
  tracks.push_back(track(5, 11, 5.1, 0.0));  // a second entry for the same object, once
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  const MoveResult& m = s.moves[0];
  EXPECT_TRUE(m.correct);
  EXPECT_DOUBLE_EQ(m.latency_s, 0.0);
  EXPECT_TRUE(m.double_match);
  EXPECT_FALSE(m.wrong_id);  // id 11's only row is on object 1: assigned to it as well
  EXPECT_EQ(s.size_errors, 1u);
  EXPECT_EQ(s.correct, 1u);
}

TEST(EvalObjects, OneIdOnTwoObjectsIsASizeError) {
  Truth t = twoObjects();
  // Object 2 stands right next to object 1's new place.
  for (auto& r : t.rows) {
    if (r.id == 2) r.x = 5.0, r.y = 0.2;
  }
  std::vector<TrackRow> tracks;
  for (std::size_t k = 0; k < 20; ++k) tracks.push_back(track(k, 10, k < 3 ? 0.0 : 5.0, 0.1));
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  EXPECT_TRUE(s.moves[0].correct);
  EXPECT_TRUE(s.moves[0].double_match);
  EXPECT_EQ(s.size_errors, 1u);
}

TEST(EvalObjects, FalseObjectFarFromEveryBodyIsStatic) {
  Truth t = twoObjects();
  t.rows.push_back({0, 0, BodyKind::Person, 1, -3, -3, 0.4, 10});
  std::vector<TrackRow> tracks;
  addStill(tracks, 20);
  // Id 30 sits on a wall for 4 scans, near the person once (0.4 m from its disc): mostly far.
  for (std::size_t k = 1; k < 5; ++k) tracks.push_back(track(k, 30, 8.0, 8.0));
  tracks.push_back(track(0, 30, -3.0, -2.4));
  // Id 31 is near object 2 for 3 of its 5 rows: not static.
  for (std::size_t k = 0; k < 3; ++k) tracks.push_back(track(k, 31, 0.0, 3.5));
  for (std::size_t k = 3; k < 5; ++k) tracks.push_back(track(k, 31, 9.0, 9.0));
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  EXPECT_EQ(s.static_as_objects, 1u);
  ASSERT_EQ(s.ids.size(), 3u);
  EXPECT_FALSE(s.ids[0].static_object);
  EXPECT_TRUE(s.ids[1].static_object);
  EXPECT_EQ(s.ids[1].far_rows, 4u);
  EXPECT_EQ(s.ids[1].matches, 0u);
  EXPECT_FALSE(s.ids[2].static_object);
  EXPECT_EQ(s.people_as_objects, 0u);
}

TEST(EvalObjects, AnObjectOnAPersonIsAPersonDetectedAsAnObject) {
  Truth t = twoObjects();
  for (std::size_t k = 0; k < 20; ++k) {
    t.rows.push_back({k, static_cast<double>(k), BodyKind::Person, 1, -3, -3, 0.45, 10});
  }
  std::vector<TrackRow> tracks;
  addStill(tracks, 20);
  // Id 40: a leg of person 1, 0.15 m from their centre, for 10 scans.
  for (std::size_t k = 5; k < 15; ++k) tracks.push_back(track(k, 40, -3.15, -3.0));
  const ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  EXPECT_EQ(s.people_as_objects, 1u);
  EXPECT_EQ(s.static_as_objects, 0u);
}

TEST(EvalObjects, LatencyMedianAndMaxInSecondsAndScans) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 2, 3}), 2.5);
  EXPECT_TRUE(std::isnan(median({})));

  // Three moves of three objects, detected 0, 1 and 4 scans (0.5 s each) after visibility.
  std::vector<TruthRow> rows;
  std::vector<TruthMove> moves;
  std::vector<TrackRow> tracks;
  const int delays[3] = {0, 1, 4};
  for (int o = 1; o <= 3; ++o) {
    const double y = 2.0 * o;
    moves.push_back({o, o, 1.0, 1.0, {0, y}, {4, y}});
    for (std::size_t k = 0; k < 30; ++k) {
      const double time = 0.5 * static_cast<double>(k);
      const double x = time < 1.0 ? 0.0 : 4.0;
      rows.push_back({k, time, BodyKind::Object, o, x, y, 0.2, 5});
      if (k < 2 || k >= 2 + static_cast<std::size_t>(delays[o - 1])) {
        tracks.push_back(track(k, 100 + o, x, y));
      }
    }
  }
  const ObjectScores s = evaluateObjects(rows, moves, tracks);
  ASSERT_EQ(s.correct, 3u);
  EXPECT_EQ(s.moves[0].visible_scan, 2u);
  EXPECT_EQ(s.latency.count, 3u);
  EXPECT_DOUBLE_EQ(s.latency.median_s, 0.5);
  EXPECT_DOUBLE_EQ(s.latency.max_s, 2.0);
  EXPECT_DOUBLE_EQ(s.latency.median_scans, 1.0);
  EXPECT_DOUBLE_EQ(s.latency.max_scans, 4.0);
}

TEST(EvalObjects, TracksAfterTheTruthAreAnError) {
  const Truth t = twoObjects(5);
  EXPECT_THROW(evaluateObjects(t.rows, t.moves, {track(7, 1, 0, 0)}), std::invalid_argument);
}

// ---- cells ------------------------------------------------------------------------------

// A 5 x 5 grid of 1 m cells on [0, 5) x [0, 5).
GridGeometry fiveByFive() {
  return {0.0, 0.0, 1.0, 5, 5};
}

CellMask maskOf(const char* rows[5]) {  // rows[0] is the top (iy = 4)
  CellMask m(25, 0);
  for (int r = 0; r < 5; ++r) {
    for (int ix = 0; ix < 5; ++ix) m[(4 - r) * 5 + ix] = rows[r][ix] == '#';
  }
  return m;
}

TEST(EvalCells, SegmentTouchesTheCellsOnBothSidesOfABorder) {
  const GridGeometry g = fiveByFive();
  CellMask m(g.cells(), 0);
  rasteriseSegment({{0.5, 2.0}, {2.5, 2.0}}, g, m);  // on the border between rows 1 and 2
  const char* expected[5] = {".....", ".....", "###..", "###..", "....."};
  EXPECT_EQ(m, maskOf(expected));
}

TEST(EvalCells, DiscCoversTheCellsItOverlaps) {
  const GridGeometry g = fiveByFive();
  CellMask m(g.cells(), 0);
  rasteriseDisc({2.5, 2.5}, 0.6, g, m);
  const char* expected[5] = {".....", "..#..", ".###.", "..#..", "....."};
  EXPECT_EQ(m, maskOf(expected));
}

TEST(EvalCells, WallImagePixelsCoverTheCellsTheyOverlap) {
  const GridGeometry g = fiveByFive();
  sim::WallGrid w;
  w.resolution = 0.5;
  w.origin = {1.0, 1.0};
  w.width = 2;
  w.height = 1;
  w.wall = {0, 1};  // the pixel [1.5, 2) x [1, 1.5): inside cell (1, 1) only
  CellMask m(g.cells(), 0);
  rasteriseWallGrid(w, g, m);
  CellMask expected(g.cells(), 0);
  expected[g.index(1, 1)] = 1;
  EXPECT_EQ(m, expected);
}

TEST(EvalCells, SaDaOnAHandMadeMap) {
  const GridGeometry g = fiveByFive();
  CellTruth truth;
  const char* walls[5] = {"#####", ".....", ".....", ".....", "....."};
  const char* dyn[5] = {".....", ".##..", ".....", "...#.", "....."};
  truth.static_cells = maskOf(walls);
  truth.dynamic_cells = maskOf(dyn);
  // S holds the wall at x = 1 and one row down at x = 0: x = 0, 1, 2 are kept (x = 0 and 2 by
  // a 4-neighbour), x = 3 is lost; one dynamic cell is still occupied; the top-right cell was
  // never observed.
  const char* occ[5] = {".#...", "#....", ".....", "...#.", "....."};
  const char* unseen[5] = {"....#", ".....", ".....", ".....", "....."};
  const CellMask occupied = maskOf(occ), not_observed = maskOf(unseen);
  std::vector<float> s_occ(g.cells());
  CellMask observed(g.cells());
  for (std::size_t i = 0; i < g.cells(); ++i) {
    s_occ[i] = occupied[i] ? 0.9f : 0.2f;
    observed[i] = !not_observed[i];
  }
  const CellScores c = scoreStaticMap(s_occ, truth, observed, g);
  EXPECT_EQ(c.static_cells, 4u);  // the unobserved wall cell does not count
  EXPECT_EQ(c.static_kept, 3u);
  EXPECT_EQ(c.dynamic_cells, 3u);
  EXPECT_EQ(c.dynamic_clear, 2u);
  EXPECT_DOUBLE_EQ(c.sa, 75.0);
  EXPECT_NEAR(c.da, 200.0 / 3, 1e-9);
  EXPECT_NEAR(c.aa, std::sqrt(75.0 * 200.0 / 3), 1e-9);
  EXPECT_NEAR(c.ha, 2 * 75.0 * (200.0 / 3) / (75.0 + 200.0 / 3), 1e-9);
}

TEST(EvalCells, PrecisionRecallWithOneCellTolerance) {
  const GridGeometry g = fiveByFive();
  const char* t[5] = {"#####", ".....", ".....", ".....", "....."};
  const char* p[5] = {"###..", "#....", ".....", "..#..", "....."};
  const CellMask observed(g.cells(), 1);
  const PrecisionRecall pr = scoreOccupied(maskOf(p), maskOf(t), observed, g);
  EXPECT_EQ(pr.predicted, 5u);
  EXPECT_EQ(pr.predicted_right, 4u);  // the stray one in the middle is wrong
  EXPECT_EQ(pr.truth, 5u);
  EXPECT_EQ(pr.truth_found, 4u);  // x = 3 by its neighbour at x = 2; x = 4 missed
  EXPECT_DOUBLE_EQ(pr.precision, 80.0);
  EXPECT_DOUBLE_EQ(pr.recall, 80.0);
}

TEST(EvalCells, TruthKeepsObjectsOutOfDynamicUntilTheirFirstMove) {
  const GridGeometry g = fiveByFive();
  sim::StaticWorld world;
  world.segments.push_back({{0.0, 4.5}, {5.0, 4.5}});  // the top row
  std::vector<TruthRow> rows = {
      {0, 0, BodyKind::Object, 1, 0.5, 0.5, 0.4, 5},  // before its move: not dynamic
      {1, 1, BodyKind::Object, 1, 2.5, 0.5, 0.4, 5},  // after: dynamic
      {1, 1, BodyKind::Object, 2, 4.5, 0.5, 0.4, 5},  // never moves: neither
      {0, 0, BodyKind::Person, 1, 2.5, 4.5, 0.4, 5},  // on the wall: static wins
      {1, 1, BodyKind::Person, 1, 2.5, 2.5, 0.4, 5},  // a person: dynamic
  };
  const std::vector<TruthMove> moves = {{1, 1, 0.5, 1.0, {0.5, 0.5}, {2.5, 0.5}}};
  const CellTruth t = cellTruth(world, rows, moves, g);
  const char* st[5] = {"#####", ".....", ".....", ".....", "....."};
  const char* dy[5] = {".....", ".....", "..#..", ".....", "..#.."};
  const char* end[5] = {"#####", ".....", "..#..", ".....", "..#.#"};
  EXPECT_EQ(t.static_cells, maskOf(st));
  EXPECT_EQ(t.dynamic_cells, maskOf(dy));
  EXPECT_EQ(t.world_at_end, maskOf(end));
}

TEST(EvalCells, ObservedMeansOffThePriorInAnyLayer) {
  const std::vector<float> a = {0.5f, 0.7f, 0.5f}, b = {0.5f, 0.5f, 0.3f};
  EXPECT_EQ(observedCells({&a, &b}), (CellMask{0, 1, 1}));
  EXPECT_TRUE(std::isnan(harmonicMean(std::nan(""), 50)));
  EXPECT_DOUBLE_EQ(harmonicMean(0, 0), 0.0);
}

// ---- the command end to end -----------------------------------------------------------------

TEST(EvalCommand, TinyScenarioWritesMetricsAndReport) {
  const std::string src = DYNAMAP_SOURCE_DIR;
  const std::string out = test::tempDir("eval_tiny") + "/result";
  std::string output;
  const int status = test::run(
      std::string(DYNAMAP_EXE) + " eval --scenario " + src + "/config/scenarios/tiny.ini --truth " +
          src + "/rawlogs/tiny --result " + out + " --config " + src + "/config/default.ini",
      &output);
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("correctly detected"), std::string::npos) << output;
  const std::string metrics = test::readFile(out + "/metrics.json");
  const std::string report = test::readFile(out + "/report.md");
  EXPECT_NE(metrics.find("\"scenario\": \"tiny\""), std::string::npos);
  EXPECT_NE(metrics.find("\"moves_total\": 2,"), std::string::npos);
  EXPECT_NE(metrics.find("\"dynamap_sa\": "), std::string::npos);
  EXPECT_EQ(metrics.back(), '\n');
  EXPECT_EQ(metrics.rfind("}\n"), metrics.size() - 2);
  EXPECT_NE(report.find("# dynamap eval: tiny"), std::string::npos);
  EXPECT_NE(report.find("| move |"), std::string::npos);

  // Deterministic: a second evaluation of the same result gives the same bytes.
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " eval --scenario " + src +
                          "/config/scenarios/tiny.ini --truth " + src +
                          "/rawlogs/tiny/tiny --result " + out,
                      &output),
            0)
      << output;
  EXPECT_EQ(test::readFile(out + "/metrics.json"), metrics);

  // --summary reads it back.
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " eval --summary " + out, &output), 0) << output;
  // Each row of the summary carries the result's own figures: the row "correctly detected"
  // ends with this result's value from metrics.json (the paper's columns come first).
  const std::string key = "\"correctly_detected\": ";
  const auto at = metrics.find(key);
  ASSERT_NE(at, std::string::npos) << metrics;
  const std::string value = metrics.substr(at + key.size(), metrics.find_first_of(",\n", at) -
                                                                 at - key.size());
  std::istringstream lines(output);
  std::string row;
  for (std::string l; std::getline(lines, l);) {
    if (l.rfind("correctly detected", 0) == 0) row = l;
  }
  ASSERT_FALSE(row.empty()) << output;
  const std::string ours = row.substr(row.find('|') + 1);
  EXPECT_EQ(std::stoi(ours), std::stoi(value)) << row;

  // A result evaluated by an earlier release, without the figures eval gained since: "n/a".
  const std::string older = out + "/older";
  std::filesystem::create_directories(older);
  const std::string cut = "  \"people_detected_as_objects\": 0,\n";
  ASSERT_NE(metrics.find(cut), std::string::npos) << metrics;
  std::string old_metrics = metrics;
  old_metrics.erase(old_metrics.find(cut), cut.size());
  { std::ofstream(older + "/metrics.json") << old_metrics; }
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " eval --summary " + older, &output), 0) << output;
  const auto line_at = output.find("people detected as objects");
  ASSERT_NE(line_at, std::string::npos) << output;
  const std::string line = output.substr(line_at, output.find('\n', line_at) - line_at);
  EXPECT_NE(line.find("| n/a"), std::string::npos) << line;
}

/// A tracks.csv of a perfect tracker: every object seen by a beam, under its own number.
void writePerfectTracks(const std::string& truth_csv, const std::string& tracks_csv) {
  std::ifstream in(truth_csv);
  std::ofstream out(tracks_csv);
  out << "scan_index,t,object_id,cx,cy,size_m,x_min,x_max,y_min,y_max\n";
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::vector<std::string> f;
    for (std::string x; std::getline(s, x, ',');) f.push_back(x);
    if (f[2] != "object" || f[7] == "0") continue;
    out << f[0] << "," << f[1] << "," << f[3] << "," << f[4] << "," << f[5] << "," << f[6]
        << ",0,0,0,0\n";
  }
}

TEST(EvalCommand, HandWrittenPerfectTracksAreAllCorrect) {
  const std::string src = DYNAMAP_SOURCE_DIR;
  const std::string out = test::tempDir("eval_perfect") + "/result";
  const std::string cmd = std::string(DYNAMAP_EXE) + " eval --scenario " + src +
                          "/config/scenarios/tiny.ini --truth " + src + "/rawlogs/tiny --result " +
                          out + " --config " + src + "/config/default.ini";
  std::string output;
  ASSERT_EQ(test::run(cmd, &output), 0) << output;  // maps the result first
  writePerfectTracks(src + "/rawlogs/tiny/tiny.objects.csv", out + "/tracks.csv");
  ASSERT_EQ(test::run(cmd, &output), 0) << output;
  const std::string metrics = test::readFile(out + "/metrics.json");
  EXPECT_NE(metrics.find("\"correctly_detected\": 2,"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"not_detected\": 0,"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"static_detected_as_objects\": 0,"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"latency_max_s\": 0.0,"), std::string::npos) << metrics;

  std::ofstream(out + "/tracks.csv", std::ios::app) << "12,2.4,7,1.0\n";
  EXPECT_EQ(test::run(cmd, &output), 1) << output;
  EXPECT_NE(output.find("tracks.csv:"), std::string::npos) << output;
  EXPECT_NE(output.find("expected 10 fields, got 4"), std::string::npos) << output;
}

TEST(EvalCommand, MalformedTruthLineNamesFileAndLine) {
  const std::string src = DYNAMAP_SOURCE_DIR;
  const std::string dir = test::tempDir("eval_bad");
  namespace fs = std::filesystem;
  for (const char* ext : {".rawlog", ".moves.csv"}) {
    fs::copy_file(src + "/rawlogs/tiny/tiny" + ext, dir + "/tiny" + ext);
  }
  {
    std::ofstream o(dir + "/tiny.objects.csv");
    o << "scan_index,t,kind,id,x,y,diameter,hits\n0,0.000,object,1,0.0,0.0,0.300,12\n"
         "1,0.200,object,1,zero,0.0,0.300,12\n";
  }
  std::string output;
  const int status =
      test::run(std::string(DYNAMAP_EXE) + " eval --scenario " + src +
                    "/config/scenarios/tiny.ini --truth " + dir + "/tiny --result " + dir + "/out",
                &output);
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("tiny.objects.csv:3: x: not a number"), std::string::npos) << output;
}

// ---- absolute trajectory error ----------------------------------------------------------------

TEST(EvalTrajectory, KnownOffsetsGiveTheirRmse) {
  const std::vector<TimedPose> truth = {{0, 0, 0, 0}, {1, 1, 0, 0}, {2, 2, 0, 0}, {3, 3, 0, 0}};
  // First pose exact, then 3 cm and 4 cm off, and 0.02 rad off in heading once.
  const std::vector<TimedPose> est = {
      {0, 0, 0, 0}, {1, 1.03, 0, 0}, {2, 2, 0.04, 0.02}, {3, 3, 0, 0}};
  const TrajectoryError e = trajectoryError(est, truth);
  EXPECT_EQ(e.matched, 4u);
  EXPECT_EQ(e.unmatched, 0u);
  EXPECT_NEAR(e.rmse_xy_m, std::sqrt((0.03 * 0.03 + 0.04 * 0.04) / 4), 1e-12);
  EXPECT_NEAR(e.rmse_phi_rad, std::sqrt(0.02 * 0.02 / 4), 1e-12);
  EXPECT_NEAR(e.max_xy_m, 0.04, 1e-12);
}

TEST(EvalTrajectory, AnEstimateInItsOwnFrameIsAnchoredAtTheFirstPose) {
  // The truth starts at (5, 2) facing +y; the estimate is the same path from the origin facing
  // +x (a SLAM run's own frame): after anchoring it is exact.
  const std::vector<TimedPose> truth = {
      {10, 5, 2, M_PI / 2}, {11, 5, 3, M_PI / 2}, {12, 4, 3, M_PI}};
  const std::vector<TimedPose> est = {{10, 0, 0, 0}, {11, 1, 0, 0}, {12, 1, 1, M_PI / 2}};
  const TrajectoryError e = trajectoryError(est, truth);
  EXPECT_EQ(e.matched, 3u);
  EXPECT_NEAR(e.rmse_xy_m, 0, 1e-9);
  EXPECT_NEAR(e.rmse_phi_rad, 0, 1e-9);
}

TEST(EvalTrajectory, PosesWithoutTruthAtTheirTimeAreCountedNotScored) {
  const std::vector<TimedPose> truth = {{0, 0, 0, 0}, {1, 1, 0, 0}};
  const std::vector<TimedPose> est = {{0, 0, 0, 0}, {0.5, 9, 9, 0}, {1.0005, 1.1, 0, 0}};
  const TrajectoryError e = trajectoryError(est, truth);
  EXPECT_EQ(e.matched, 2u);
  EXPECT_EQ(e.unmatched, 1u);
  EXPECT_NEAR(e.rmse_xy_m, std::sqrt(0.01 / 2), 1e-9);
  EXPECT_TRUE(std::isnan(trajectoryError({{7, 0, 0, 0}}, truth).rmse_xy_m));
}

TEST(EvalTrajectory, HeadingErrorWrapsAroundPi) {
  const std::vector<TimedPose> truth = {{0, 0, 0, 0}, {1, 0, 0, M_PI - 0.01}};
  const std::vector<TimedPose> est = {{0, 0, 0, 0}, {1, 0, 0, -M_PI + 0.01}};
  EXPECT_NEAR(trajectoryError(est, truth).rmse_phi_rad, std::sqrt(0.02 * 0.02 / 2), 1e-9);
}

}  // namespace
}  // namespace dynamap

namespace dynamap {
namespace {

TruthRow personAt(std::size_t scan, int id, double x, double y, int hits = 5) {
  TruthRow r;
  r.scan_index = scan;
  r.kind = sim::BodyKind::Person;
  r.id = id;
  r.x = x;
  r.y = y;
  r.diameter = 0.4;
  r.hits = hits;
  return r;
}

TEST(ClearMot, CountsMatchesMissesFalsePositivesAndSwitches) {
  std::vector<TruthRow> truth;
  std::vector<PersonTrackRow> tracks;
  for (std::size_t k = 0; k < 10; ++k) {
    truth.push_back(personAt(k, 1, 0.1 * k, 0));
    truth.push_back(personAt(k, 2, 0.1 * k, 3, k == 9 ? 2 : 5));  // scan 9: 2 beams, not counted
    // Person 1: track 7 at 0.1 m, but scans 6.. track 8 takes over (one switch); scan 3 missed.
    if (k != 3) tracks.push_back({k, k < 6 ? 7 : 8, 0.1 * k + 0.1, 0});
    // Person 2: track 9 at 0.05 m every scan (at scan 9 matched to an uncounted person).
    tracks.push_back({k, 9, 0.1 * k, 3.05});
    // A ghost 5 m from everyone at scans 0 and 1.
    if (k < 2) tracks.push_back({k, 10, 5, 5});
  }
  const MotScores s = evaluateClearMot(truth, tracks);
  EXPECT_EQ(s.ground_truth, 19u);
  EXPECT_EQ(s.matches, 18u);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.false_positives, 2u);
  EXPECT_EQ(s.id_switches, 1u);
  ASSERT_EQ(s.switches.size(), 1u);  // where it happened, for report.md
  EXPECT_EQ(s.switches[0].scan_index, 6u);
  EXPECT_EQ(s.switches[0].person, 1);
  EXPECT_EQ(s.switches[0].from_id, 7);
  EXPECT_EQ(s.switches[0].to_id, 8);
  EXPECT_NEAR(s.mota, 1.0 - 4.0 / 19.0, 1e-12);
  EXPECT_NEAR(s.motp_m, (9 * 0.1 + 9 * 0.05) / 18.0, 1e-9);
  EXPECT_EQ(s.people, 2u);
  EXPECT_EQ(s.track_ids, 4u);
}

// A walker at 1 m/s (5 scans/s) who stands 3 s at x = 2 and then walks on: a switch as they walk
// off is at a stop, one 10 s later is not, nor one just after the walker turns back (no stop).
TEST(ClearMot, SwitchesWhileStandingOrWalkingOffAreAtAStop) {
  std::vector<TruthRow> truth;
  std::vector<PersonTrackRow> tracks;
  double x = 0;
  for (std::size_t k = 0; k < 150; ++k) {
    const double t = 0.2 * static_cast<double>(k);
    if (t >= 2.0 && t < 5.0) {
      x = 2.0;  // standing
    } else {
      x = t < 2.0 ? t : (t < 20.0 ? 2.0 + (t - 5.0) : 17.0 - (t - 20.0));  // back from x = 17
    }
    TruthRow r = personAt(k, 1, x, 0);
    r.t = t;
    truth.push_back(r);
    // Track 1 until 5.4 s (walking off), 2 until 15 s, 3 until 20.4 s (after the turn), then 4.
    const int id = t < 5.4 ? 1 : (t < 15.0 ? 2 : (t < 20.4 ? 3 : 4));
    tracks.push_back({k, id, x, 0});
  }
  const MotScores s = evaluateClearMot(truth, tracks);
  ASSERT_EQ(s.id_switches, 3u);
  EXPECT_EQ(s.id_switches_at_stops, 1u);
  EXPECT_TRUE(s.switches[0].at_stop);   // 5.4 s: walking off, 0.4 s after the stop
  EXPECT_FALSE(s.switches[1].at_stop);  // 15 s: 10 s after it
  EXPECT_FALSE(s.switches[2].at_stop);  // 20.4 s: the turn at x = 17 is no stop
  MotOptions o;
  o.after_stop_s = 0.2;  // a shorter walking-off window leaves the first switch out too
  EXPECT_EQ(evaluateClearMot(truth, tracks, o).id_switches_at_stops, 0u);
}

TEST(ClearMot, TrackBeyondTheGateIsAMissAndAFalsePositive) {
  const std::vector<TruthRow> truth = {personAt(0, 1, 0, 0)};
  const std::vector<PersonTrackRow> tracks = {{0, 1, 0.8, 0}};
  const MotScores s = evaluateClearMot(truth, tracks);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.false_positives, 1u);
  EXPECT_DOUBLE_EQ(s.mota, -1.0);
}

}  // namespace
}  // namespace dynamap

namespace dynamap {
namespace {

// ---- dynamap eval --input LOG --trajectory FILE ---------------------------------------------

/// The truth of the bundled tiny log, with every pose from scan `from` on moved by (dx, dy) and
/// every timestamp by dt, into `path`.
void writeMovedTruth(const std::string& path, std::size_t from, double dx, double dy,
                     double dt = 0) {
  std::ifstream in(std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.gt.txt");
  std::ofstream out(path);
  out << std::fixed << std::setprecision(6);
  double t, x, y, phi;
  for (std::size_t i = 0; in >> t >> x >> y >> phi; ++i) {
    const bool moved = i >= from;
    out << t + dt << ' ' << x + (moved ? dx : 0) << ' ' << y + (moved ? dy : 0) << ' ' << phi
        << '\n';
  }
}

/// The figure after `what` ("global ", "local ") in eval's consistency line, in mm.
double figure(const std::string& out, const std::string& what) {
  const auto at = out.find(what);
  EXPECT_NE(at, std::string::npos) << out;
  return at == std::string::npos ? NAN : std::stod(out.substr(at + what.size()));
}

TEST(EvalConsistency, AMapDoubledByAJumpScoresWorseGloballyNotLocally) {
  const std::string dir = test::tempDir("consistency");
  const std::string log = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.rawlog";
  const std::string cmd = std::string(DYNAMAP_EXE) + " eval --input " + log + " --trajectory ";
  writeMovedTruth(dir + "/truth.txt", 0, 0, 0);
  writeMovedTruth(dir + "/jump.txt", 150, 0.1, 0.05);  // the second half 11 cm off the first
  std::string truth, jump;
  ASSERT_EQ(test::run(cmd + dir + "/truth.txt", &truth), 0) << truth;
  ASSERT_EQ(test::run(cmd + dir + "/jump.txt", &jump), 0) << jump;
  EXPECT_NE(truth.find("301 scans scored, 0 without a pose"), std::string::npos) << truth;
  EXPECT_GT(figure(jump, "global "), figure(truth, "global ") + 10) << truth << jump;
  // One pair of consecutive scans of 300 straddles the jump.
  EXPECT_NEAR(figure(jump, "local "), figure(truth, "local "), 1.0) << truth << jump;
  // The same bytes again.
  std::string again;
  ASSERT_EQ(test::run(cmd + dir + "/jump.txt", &again), 0);
  EXPECT_EQ(again, jump);
}

TEST(EvalConsistency, PosesAtNoScanTimeAndMisusedFlagsAreErrors) {
  const std::string dir = test::tempDir("consistency-err");
  const std::string log = std::string(DYNAMAP_SOURCE_DIR) + "/rawlogs/tiny/tiny.rawlog";
  const std::string exe = std::string(DYNAMAP_EXE) + " eval";
  writeMovedTruth(dir + "/late.txt", 0, 0, 0, 1000);  // every pose 1000 s after the log
  std::string out;
  EXPECT_EQ(test::run(exe + " --input " + log + " --trajectory " + dir + "/late.txt", &out), 1);
  EXPECT_NE(out.find(dir + "/late.txt: no pose at the time of any scan of " + log),
            std::string::npos)
      << out;
  EXPECT_EQ(test::run(exe + " --input " + log, &out), 2) << out;  // nothing to lay out
  std::ofstream(dir + "/empty.txt") << "% no poses\n";
  EXPECT_EQ(test::run(exe + " --input " + log + " --trajectory " + dir + "/empty.txt", &out), 1);
  EXPECT_NE(out.find("no pose (expected"), std::string::npos) << out;
}

// Real scans: an object left where it stood (the robot never looked back) and the log's own
// change are set aside; a report where nothing ever stood stays a static part.
TEST(EvalObjects, RealScansSetAsideWhatIsNoStaticPart) {
  const Truth t = twoObjects();
  std::vector<TrackRow> tracks;
  addStill(tracks, 5);
  for (std::size_t k = 0; k < 20; ++k) {
    tracks.push_back(track(k, 7, 0.02, 0.0));  // object 1's first place, kept after it left
    tracks.push_back(track(k, 8, 9.0, 9.0));   // something of the log's own
    tracks.push_back(track(k, 9, -7.0, 2.0));  // nothing ever stood there
  }
  ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  ASSERT_EQ(s.static_as_objects, 3u);
  setAsideLogOwn(s, tracks, {{3, 9.1, 9.0}, {4, 9.0, 9.2}, {5, 9.0, 9.0}, {6, 9, 9}, {7, 9, 9},
                             {8, 9, 9}, {9, 9, 9}, {10, 9, 9}, {11, 9, 9}, {12, 9, 9}, {13, 9, 9}});
  EXPECT_EQ(s.log_own_objects, 1u);
  EXPECT_EQ(s.static_as_objects, 2u);
  setAsideLeftBehind(s, tracks, t.rows);
  EXPECT_EQ(s.left_behind_objects, 1u);
  EXPECT_EQ(s.static_as_objects, 1u);
  for (const IdAssignment& a : s.ids) {
    EXPECT_EQ(a.static_object, a.track_id == 9) << a.track_id;
    EXPECT_EQ(a.log_own, a.track_id == 8) << a.track_id;
    EXPECT_EQ(a.left_behind, a.track_id == 7) << a.track_id;
  }
}

// A log whose scans come seconds apart: the detection window is 50 scans, not 10 s.
TEST(EvalObjects, TheWindowIsFiftyScansOnASlowLog) {
  Truth t;
  for (std::size_t k = 0; k < 80; ++k) {
    const double time = 3.0 * static_cast<double>(k);
    t.rows.push_back({k, time, BodyKind::Object, 1, time < 30 ? 0.0 : 5.0, 0.0, 0.3, 10});
  }
  t.moves.push_back({1, 1, 29.0, 29.0, {0, 0}, {5, 0}});
  std::vector<TrackRow> tracks;
  for (std::size_t k = 0; k < 80; ++k) tracks.push_back(track(k, 4, k < 10 ? 0.0 : k < 16 ? -3 : 5, 0));
  ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  ASSERT_EQ(s.moves.size(), 1u);
  EXPECT_TRUE(s.moves[0].correct);  // found 6 scans (18 s) after it was first seen
  EXPECT_EQ(s.moves[0].latency_scans, 6u);
  EXPECT_DOUBLE_EQ(s.moves[0].latency_s, 18.0);
}

}  // namespace
}  // namespace dynamap
