// The evaluation's definitions (docs/evaluation.md) on tiny hand-written truth and tracks, and
// `dynamap eval` end to end on the bundled tiny scenario. Cells: cell_scores_test.cpp; CLEAR MOT:
// clear_mot_test.cpp.

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
  std::string old_metrics = metrics;
  for (const char* key : {"people_detected_as_objects", "missed_few_views"}) {
    const std::string cut = std::string("  \"") + key + "\": 0,\n";
    ASSERT_NE(old_metrics.find(cut), std::string::npos) << metrics;
    old_metrics.erase(old_metrics.find(cut), cut.size());
  }
  { std::ofstream(older + "/metrics.json") << old_metrics; }
  ASSERT_EQ(test::run(std::string(DYNAMAP_EXE) + " eval --summary " + older, &output), 0) << output;
  for (const char* label : {"people detected as objects", "  seen in few scans"}) {
    const auto line_at = output.find(label);
    ASSERT_NE(line_at, std::string::npos) << output;
    const std::string line = output.substr(line_at, output.find('\n', line_at) - line_at);
    EXPECT_NE(line.find("| n/a"), std::string::npos) << line;
  }
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

// The log's own change is set aside by its place from the scan it was first reported at on:
// the table may keep it longer than the unedited log's did (another object took its id there).
// Rows at that place before the change happened are no change of the log's.
TEST(EvalObjects, TheLogsOwnPlaceCountsFromItsFirstReportOn) {
  const Truth t = twoObjects();
  std::vector<TrackRow> tracks;
  addStill(tracks, 5);
  for (std::size_t k = 0; k < 20; ++k) {
    tracks.push_back(track(k, 8, 9.0, 9.0));   // the unedited run: scans 5-7 only
    tracks.push_back(track(k, 9, -7.0, 2.0));  // the unedited run: from scan 15 on
  }
  ObjectScores s = evaluateObjects(t.rows, t.moves, tracks);
  ASSERT_EQ(s.static_as_objects, 2u);
  setAsideLogOwn(s, tracks, {{5, 9.1, 9.0}, {6, 9.0, 9.0}, {7, 9.0, 9.1}, {15, -7.0, 2.0},
                             {16, -7.0, 2.0}, {17, -7.0, 2.0}, {18, -7.0, 2.0}, {19, -7.0, 2.0}});
  EXPECT_EQ(s.log_own_objects, 1u);
  EXPECT_EQ(s.static_as_objects, 1u);
  for (const IdAssignment& a : s.ids) EXPECT_EQ(a.log_own, a.track_id == 8) << a.track_id;
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
