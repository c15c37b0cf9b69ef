// dynamap eval: a mapping result scored against the simulator's ground truth.
// The metrics are defined in src/evaluation/ and docs/evaluation.md, the truth and result files
// read by evaluation/result_files, the reports written by eval_report; this file runs the mapper
// and the plain MRPT baseline when needed and puts the evaluation together.

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "dynamap/base/ini.h"
#include "dynamap/evaluation/evaluation.h"
#include "dynamap/evaluation/result_files.h"
#include "dynamap/localization/consistency.h"
#include "eval_report.h"
#ifdef DYNAMAP_HAVE_ROSBAG
#include "dynamap/evaluation/bag_people_truth.h"
#endif
#include "dynamap/input/open_source.h"
#include "dynamap/mapping/dynamic_map_options.h"
#include "dynamap/outputs/json.h"
#include "dynamap/outputs/map_job.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/scenario.h"

namespace dynamap::app {
namespace {

namespace fs = std::filesystem;

const char* const kEvalUsage =
    "usage: dynamap eval [--scenario FILE] --truth PREFIX --result DIR [--config FILE]\n"
    "       dynamap eval --summary DIR...\n"
    "       dynamap eval --truth PREFIX --sessions DIR1 DIR2...\n"
    "       dynamap eval --truth PREFIX --trajectory FILE\n"
    "       dynamap eval --input LOG --trajectory FILE [--truth PREFIX]\n"
    "       dynamap eval --people-bag BAG --result DIR [--scan-topic T] [--person-topic T]\n\n"
    "Scores a `dynamap map` result against the simulator's ground truth: per object move\n"
    "(the paper's Table 3: correctly detected, not detected, size estimation errors, static\n"
    "parts detected as objects, latency) and per cell (SA, DA, AA, HA of the static map, and\n"
    "of a plain MRPT grid built from the same scans; precision and recall of S u D).\n"
    "PREFIX is the simulator's file prefix (rawlogs/arena/arena) or its directory\n"
    "(rawlogs/arena). When DIR has no summary.json the mapper runs first (ground-truth\n"
    "poses, --config). Prints a table and writes DIR/report.md and DIR/metrics.json.\n"
    "Without --scenario (real scans with objects added by `dynamap perturb --add-objects`) the\n"
    "walls are unknown: the object figures are scored, the cell figures know the objects only.\n"
    "--sessions scores the change reports of a multi-session scenario's sessions, mapped in\n"
    "order (DIR2 with --prior DIR1, ...), against PREFIX.changes.csv: each change found, under\n"
    "a wrong id, misplaced or missed, and the false changes; written to DIRk/changes_score.json.\n"
    "--summary prints one table of several evaluated results beside the paper's Table 3.\n"
    "The poses the result was mapped at (DIR/poses.txt) and the log's raw odometry are scored\n"
    "against the truth's poses (PREFIX.gt.txt): absolute trajectory error, RMSE of position and\n"
    "heading. --trajectory scores any `timestamp x y phi` file (e.g. another SLAM's) that way.\n"
    "--input LOG with --trajectory lays the log's scans out at the file's poses and says how\n"
    "well they lie on each other, no truth needed: the mean distance of their points to those\n"
    "of scans more than 50 scans away (global) and of the scan before (local).\n"
    "Definitions: docs/evaluation.md.";

// ---- the mapping result -------------------------------------------------------------------

/// Maps the rawlog with ground-truth poses into `dir`, as `dynamap map` would (no baseline).
void runMapper(const std::string& rawlog, MapConfig config, const std::string& dir) {
  config.poses = PoseSource::GroundTruth;
  MapJob job;
  job.input = rawlog;
  job.out_dir = dir;
  job.config = config;
  job.baseline = false;
  const MapJobResult r = runMapJob(job);
  if (!r.outcome.fault.empty()) throw InputError(r.outcome.fault);
}

mrpt::maps::COccupancyGridMap2D loadGrid(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path + ": missing (not a dynamap map result?)");
  mrpt::maps::COccupancyGridMap2D grid;
  try {
    mrpt::io::CFileGZInputStream in(path);
    auto arch = mrpt::serialization::archiveFrom(in);
    arch >> grid;
  } catch (const std::exception& e) {
    throw InputError(path + ": not a readable MRPT gridmap (" +
                     std::string(e.what()).substr(0, 200) + ")");
  }
  return grid;
}

GridGeometry geometryOf(const mrpt::maps::COccupancyGridMap2D& grid) {
  return {grid.getXMin(), grid.getYMin(), grid.getResolution(), static_cast<int>(grid.getSizeX()),
          static_cast<int>(grid.getSizeY())};
}

/// P(occupied) of `grid` at the centre of every cell of `g` (0.5 outside `grid`): grids of
/// slightly different extents are compared cell for cell.
std::vector<float> occupancyOn(const mrpt::maps::COccupancyGridMap2D& grid, const GridGeometry& g) {
  std::vector<float> out(g.cells(), 0.5f);
  for (int iy = 0; iy < g.size_y; ++iy) {
    const int gy = grid.y2idx(g.y_min + (iy + 0.5) * g.resolution);
    if (gy < 0 || gy >= static_cast<int>(grid.getSizeY())) continue;
    for (int ix = 0; ix < g.size_x; ++ix) {
      const int gx = grid.x2idx(g.x_min + (ix + 0.5) * g.resolution);
      if (gx < 0 || gx >= static_cast<int>(grid.getSizeX())) continue;
      out[g.index(ix, iy)] = 1.0f - grid.getCell(gx, gy);
    }
  }
  return out;
}

/// What a user gets without dynamap: MRPT's grid, default insertion options, the same scans and
/// poses, the resolution and extent of S.
std::vector<float> plainMrptOccupancy(const std::string& rawlog, const GridGeometry& g,
                                      const MapConfig& config) {
  PlainGrid plain(config.map, config.insertion, static_cast<float>(g.x_min),
                  static_cast<float>(g.x_min + g.size_x * g.resolution),
                  static_cast<float>(g.y_min),
                  static_cast<float>(g.y_min + g.size_y * g.resolution));
  auto source = openScanSource(rawlog, PoseSource::GroundTruth);
  for (ScanRecord rec; source->next(rec);) plain.insert(*rec.scan, rec.pose);
  return occupancyOn(plain.grid(), g);
}

// ---- the evaluation -----------------------------------------------------------------------

double objectThreshold(const std::string& result) {
  const std::string path = (fs::path(result) / "config.ini").string();
  if (!fs::exists(path)) return DynamicMapOptions{}.object_threshold;
  return IniFile::fromFile(path).getDouble("dynamic_map", "object_threshold", 0.85);
}

void evaluateCells(const sim::Scenario& scenario, const std::vector<TruthRow>& rows,
                   const std::vector<TruthMove>& moves, const std::string& rawlog,
                   const MapConfig& config, Evaluation& ev) {
  const auto s_grid = loadGrid((fs::path(ev.result) / "static.gridmap.gz").string());
  const auto d_grid = loadGrid((fs::path(ev.result) / "dynamic.gridmap.gz").string());
  const GridGeometry g = geometryOf(s_grid);
  const auto s_occ = occupancyOn(s_grid, g);
  const auto d_occ = occupancyOn(d_grid, g);
  const auto plain = plainMrptOccupancy(rawlog, g, config);
  // One set of observed cells for both maps, so their figures share a denominator.
  const CellMask observed = observedCells({&s_occ, &d_occ, &plain});
  for (auto o : observed) ev.observed += o;
  const CellTruth truth = cellTruth(scenario.world, rows, moves, g);
  ev.dynamap = scoreStaticMap(s_occ, truth, observed, g);
  ev.plain = scoreStaticMap(plain, truth, observed, g);
  ev.object_threshold = objectThreshold(ev.result);
  ev.union_pr = scoreOccupied(unionOccupied(s_occ, d_occ, ev.object_threshold), truth.world_at_end,
                              observed, g);
}

// ---- a real bag's people -------------------------------------------------------------------

/// --people-bag BAG --result DIR: CLEAR MOT of DIR/people.csv against the bag's Person messages
/// (scored on the scans they annotate), printed and written to DIR/people_metrics.json.
int scorePeopleBag(const po::variables_map& vm) {
#ifdef DYNAMAP_HAVE_ROSBAG
  const std::string bag = vm["people-bag"].as<std::string>(),
                    result = vm["result"].as<std::string>();
  const fs::path people = fs::path(result) / "people.csv", poses = fs::path(result) / "poses.txt";
  for (const fs::path& f : {people, poses}) {
    if (!fs::exists(f))
      throw InputError(f.string() + ": missing (map the bag into " + result + " first)");
  }
  const BagPeopleTruth truth = bagPeopleTruth(
      bag, bagOptions(vm), vm["person-topic"].as<std::string>(), readPoses(poses.string()));
  const MotScores m = evaluateClearMot(truth.rows, readPeople(people.string()));
  std::cout << "dynamap eval: " << result << " against " << bag << " (" << truth.messages
            << " annotations, " << truth.unplaced << " on scans without a pose)\n"
            << "  people (CLEAR MOT, gate 0.75 m)\n  MOTA " << num(m.mota, 3, "n/a") << "   MOTP "
            << num(m.motp_m, 3, "n/a") << " m   matches " << m.matches << ", misses " << m.misses
            << ", false positives " << m.false_positives << ", identity switches " << m.id_switches
            << "\n  " << m.people << " persons, " << m.track_ids << " track ids\n";
  const Json j = {{"people_bag", bag},
                  {"annotations", truth.messages},
                  {"unplaced", truth.unplaced},
                  {"mota", jnum(m.mota, 3)},
                  {"motp_m", jnum(m.motp_m, 3)},
                  {"mot_person_scans", m.ground_truth},
                  {"mot_matches", m.matches},
                  {"mot_misses", m.misses},
                  {"mot_false_positives", m.false_positives},
                  {"mot_id_switches", m.id_switches},
                  {"mot_track_ids", m.track_ids}};
  writeFileAtomically(result, "people_metrics.json",
                      [&](std::ostream& o) { o << j.dump(2) << "\n"; });
  return kExitOk;
#else
  (void)vm;
  throw std::runtime_error("this dynamap was built without ROS bag support (DYNAMAP_ROSBAG=OFF)");
#endif
}

// ---- the command --------------------------------------------------------------------------

/// The result's poses.txt, when it has one, and the log's odometry against the truth's poses.
void evaluatePoses(const std::string& result, const std::string& prefix, const std::string& rawlog,
                   Evaluation& ev) {
  const fs::path poses = fs::path(result) / "poses.txt";
  ev.have_poses = fs::exists(poses);
  if (!ev.have_poses) return;
  const auto truth = readPoses(prefix + ".gt.txt");
  ev.trajectory = trajectoryError(readPoses(poses.string()), truth);
  ev.odometry = trajectoryError(odometryPoses(rawlog), truth);
}

Evaluation evaluate(const std::string& scenario_path, const std::string& truth_given,
                    const std::string& result, const MapConfig& config) {
  const std::string prefix = truthPrefix(truth_given);
  // No scenario: a real log with added objects (perturb --add-objects), whose walls nobody knows.
  sim::Scenario scenario;
  if (!scenario_path.empty()) {
    scenario = sim::loadScenario(scenario_path);
  } else {
    scenario.name = fs::path(prefix).filename().string();
  }
  const std::string rawlog = prefix + ".rawlog";
  const auto rows = readTruthRows(prefix + ".objects.csv");
  const auto moves = readMoves(prefix + ".moves.csv");

  Evaluation ev;
  ev.scenario = scenario.name;
  if (scenario_path.empty()) {
    ev.notes.push_back(
        "no scenario: the walls are unknown, so the cell figures know the added "
        "objects only (SA, AA, HA undefined)");
  }
  ev.truth = prefix;
  ev.result = result;
  ev.moves = moves.size();
  if (!fs::exists(fs::path(result) / "summary.json")) {
    std::cerr << "dynamap eval: no mapping result in " << result << ", mapping " << rawlog << "\n";
    runMapper(rawlog, config, result);
  }
  const fs::path tracks = fs::path(result) / "tracks.csv";
  ev.have_tracks = fs::exists(tracks);
  std::vector<TrackRow> track_rows;
  if (ev.have_tracks) {
    track_rows = readTracks(tracks.string());
    keepTableRows((fs::path(result) / "objects.csv").string(), track_rows, ev.notes);
  } else
    ev.notes.push_back("the result has no tracks.csv: no object was reported");
  try {
    ev.objects = evaluateObjects(rows, moves, track_rows);
  } catch (const std::invalid_argument& e) {
    throw InputError(tracks.string() + ": " + e.what());
  }
  // Real scans (no scenario): the log's own changes and objects left where the robot never
  // looked again are no static parts; the simulator's robots see every place again.
  ev.real_scans = scenario_path.empty();
  ev.have_own = ev.real_scans && fs::exists(prefix + ".own.csv");
  if (ev.have_own) setAsideLogOwn(ev.objects, track_rows, readOwn(prefix + ".own.csv"));
  if (ev.real_scans) setAsideLeftBehind(ev.objects, track_rows, rows);
  evaluateCells(scenario, rows, moves, rawlog, config, ev);
  const fs::path people = fs::path(result) / "people.csv";
  ev.have_people = fs::exists(people);
  const std::vector<PersonTrackRow> people_rows =
      ev.have_people ? readPeople(people.string()) : std::vector<PersonTrackRow>{};
  explainMisses(ev.objects, rows, moves, track_rows, people_rows);
  ev.mot = evaluateClearMot(rows, people_rows);
  evaluatePoses(result, prefix, rawlog, ev);
  return ev;
}

/// --trajectory: `file` against the truth `given` (a pose file such as dynamap perturb's
/// gt.txt, or the simulator's prefix): the anchored ATE, then the errors that do not depend on
/// where the estimate starts.
void scoreTrajectory(const std::string& file, const std::string& given) {
  const std::string truth = std::filesystem::is_regular_file(given) && given.size() > 4 &&
                                    given.compare(given.size() - 4, 4, ".txt") == 0
                                ? given
                                : truthPrefix(given) + ".gt.txt";
  const std::vector<TimedPose> estimate = readPoses(file), reference = readPoses(truth);
  // Nothing to score is an error, not a table of n/a with exit status 0.
  if (estimate.empty()) throw InputError(file + ": no pose (expected 'timestamp x y phi' lines)");
  if (reference.empty()) throw InputError(truth + ": no pose (expected 'timestamp x y phi' lines)");
  const TrajectoryError e = trajectoryError(estimate, reference);
  std::cout << "dynamap eval: " << file << " against " << truth << ": " << e.matched
            << " poses scored, " << e.unmatched << " without truth; ATE RMSE position "
            << num(e.rmse_xy_m, 4, "n/a") << " m, heading "
            << num(e.rmse_phi_rad * 180.0 / M_PI, 3, "n/a") << " deg, max position error "
            << num(e.max_xy_m, 3, "n/a") << " m\n";
  const AlignedTrajectoryError a = alignedTrajectoryError(estimate, reference);
  std::cout << "dynamap eval: after the best rigid alignment: position RMSE "
            << num(a.aligned_rmse_xy_m, 4, "n/a") << " m; relative error over 1 m of path "
            << num(a.rel_1m_xy_m, 4, "n/a") << " m, "
            << num(a.rel_1m_phi_rad * 180.0 / M_PI, 3, "n/a") << " deg; over 10 m "
            << num(a.rel_10m_xy_m, 4, "n/a") << " m, "
            << num(a.rel_10m_phi_rad * 180.0 / M_PI, 3, "n/a") << " deg\n";
}

/// --input LOG with --trajectory FILE: the log's scans (the hits the mapper inserts, at the
/// default insertion range) laid out at the pose of FILE at each scan's timestamp, scored by
/// mapConsistency (no truth needed). Scans without a (finite) pose there are counted, not scored.
void scoreConsistency(const std::string& log, const std::string& file) {
  const std::vector<TimedPose> poses = readPoses(file);
  if (poses.empty()) throw InputError(file + ": no pose (expected 'timestamp x y phi' lines)");
  auto source = openScanSource(log, PoseSource::Fixed);
  const InsertionOptions insertion;
  const ConsistencyOptions o;
  ScanLayout layout(o);
  std::vector<mrpt::poses::CPose2D> at;
  std::size_t without_pose = 0;
  ScanRecord rec;
  while (!layout.full() && source->next(rec)) {
    const TimedPose* p = poseAtTime(poses, rec.t, 1e-3);
    if (p == nullptr || !std::isfinite(p->x) || !std::isfinite(p->y) || !std::isfinite(p->phi)) {
      ++without_pose;
      continue;
    }
    if (layout.addScan(*rec.scan, insertion)) at.emplace_back(p->x, p->y, p->phi);
  }
  if (at.empty()) throw InputError(file + ": no pose at the time of any scan of " + log);
  const Consistency c = layout.score(at);
  std::cout << "dynamap eval: " << log << " laid out at " << file << ": " << at.size()
            << " scans scored, " << without_pose << " without a pose"
            << (layout.full() ? " (the rest not read: the points kept reached their bound)" : "")
            << "; consistency: global " << num(c.global_m * 1000, 2, "n/a") << " mm ("
            << c.global_points << " points, against scans more than " << o.neighbour_scans
            << " away), local " << num(c.local_m * 1000, 2, "n/a") << " mm (" << c.local_points
            << " points, against the scan before)\n";
}

}  // namespace

static po::options_description evalOptions() {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")(
      "scenario,s", po::value<std::string>(), "the scenario file the truth was simulated from")(
      "truth,t", po::value<std::string>(),
      "the simulator's file prefix (rawlogs/arena/arena) or its directory")(
      "result,r", po::value<std::string>(), "a dynamap map output directory (mapped if empty)")(
      "config,c", po::value<std::string>(),
      "the mapper's configuration (default: the built-in defaults = config/default.ini), for\n"
      "mapping the result when it is not there yet and for the plain MRPT grid")(
      "sessions", po::value<std::vector<std::string>>()->multitoken(),
      "with --truth: score the change reports of these session results (in session order)")(
      "summary", po::value<std::vector<std::string>>()->multitoken(),
      "print one table of these evaluated result directories beside the paper's Table 3")(
      "trajectory", po::value<std::string>(),
      "only score this `timestamp x y phi` file against the truth's poses (--truth), and/or\n"
      "lay out the scans of --input at it (consistency)")(
      "input,i", po::value<std::string>(), "with --trajectory: the log the poses are of")(
      "people-bag", po::value<std::string>(),
      "score --result's people against this ROS bag's leg_tracker/Person messages")(
      "person-topic", po::value<std::string>()->default_value("/ground_truth_people_tracks"),
      "with --people-bag: the topic of the Person messages");
  addBagOptions(opts, "with --people-bag, as the bag was mapped: ");
  return opts;
}

int runEval(const Args& args) {
  const po::options_description opts = evalOptions();
  po::positional_options_description positional;
  po::variables_map vm;
  if (!parseArgs(args, opts, positional, vm, kEvalUsage)) return kExitOk;

  if (vm.count("summary")) {
    if (vm.count("scenario") || vm.count("truth") || vm.count("result")) {
      throw UsageError("--summary takes only result directories");
    }
    return runSummary(vm["summary"].as<std::vector<std::string>>(), std::cout);
  }
  if (vm.count("sessions")) {
    if (!vm.count("truth") || vm.count("scenario") || vm.count("result") || vm.count("trajectory"))
      throw UsageError("--sessions takes --truth PREFIX and the session results only");
    return scoreSessions(vm["sessions"].as<std::vector<std::string>>(),
                         vm["truth"].as<std::string>(), std::cout);
  }
  if (vm.count("people-bag")) {
    if (!vm.count("result") || vm.count("scenario") || vm.count("truth") || vm.count("trajectory"))
      throw UsageError("--people-bag takes --result (and --scan-topic, --person-topic) only");
    return scorePeopleBag(vm);
  }
  if (vm.count("trajectory")) {
    if ((!vm.count("truth") && !vm.count("input")) || vm.count("scenario") || vm.count("result")) {
      throw UsageError("--trajectory takes --truth, --input or both");
    }
    const std::string file = vm["trajectory"].as<std::string>();
    if (vm.count("truth")) scoreTrajectory(file, vm["truth"].as<std::string>());
    if (vm.count("input")) scoreConsistency(vm["input"].as<std::string>(), file);
    return kExitOk;
  }
  if (vm.count("input")) throw UsageError("--input goes with --trajectory");
  for (const char* k : {"truth", "result"}) {
    if (!vm.count(k)) throw UsageError(std::string("--") + k + " is required");
  }
  const std::string result = vm["result"].as<std::string>();
  MapConfig config;
  if (vm.count("config"))
    config = MapConfig::load(IniFile::fromFile(vm["config"].as<std::string>()));
  const Evaluation ev =
      evaluate(vm.count("scenario") ? vm["scenario"].as<std::string>() : std::string(),
               vm["truth"].as<std::string>(), result, config);
  printTable(std::cout, ev);
  writeFileAtomically(result, "metrics.json", [&](std::ostream& o) { writeMetricsJson(o, ev); });
  writeFileAtomically(result, "report.md", [&](std::ostream& o) { writeReport(o, ev); });
  return kExitOk;
}

}  // namespace dynamap::app
