// dynamap map: a log in, the static map, the dynamic map and their pictures out.

#include <signal.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli.h"
#include "dynamap/base/ini.h"
#include "dynamap/base/printable.h"
#include "dynamap/input/fixed_pose.h"
#include "dynamap/outputs/map_job.h"
#include "map_command.h"

namespace dynamap::app {
namespace {

const char* const kMapUsage =
    "usage: dynamap map --input FILE [--config FILE] [--out DIR] [--poses SOURCE]\n"
    "                   [--fixed-pose \"X Y PHI\"] [--frames-every N] [--no-baseline]\n"
    "                   [--skip-bad-lines] [--fov DEG] [--carmen-odometry laser|odom]\n"
    "                   [--prior DIR [--initial-pose \"X Y PHI\"]]\n"
    "                   [--scan-topic T] [--odom-topic T]\n"
    "                   [--odom-frame F] [--base-frame F] [--gt-frame F] [--verbose]\n\n"
    "Builds the static map S and the dynamic map D from a log (MRPT rawlog, MRPT simplemap,\n"
    "CARMEN log, plain or gz, or ROS 1 bag, told apart by content) and writes into DIR:\n"
    "static.png, dynamic.png, overlay.png, static.gridmap.gz and dynamic.gridmap.gz (MRPT),\n"
    "static.pgm + static.yaml (ROS map_server), config.ini (the effective configuration),\n"
    "summary.json, poses.txt (timestamp x y phi: the pose each scan was mapped at), the\n"
    "object table: objects.csv, events.csv, tracks.csv, people.csv (each person tracked, per\n"
    "scan), graph.g2o (pose source slam: the optimised pose graph), and mrpt_plain.png:\n"
    "the plain MRPT grid of the same scans, compared with S in summary.json, and\n"
    "session.json: what the next session of the same building starts from (--prior).\n"
    "--prior DIR continues the session mapped into DIR: this log's S starts from DIR's, its\n"
    "objects keep their ids, and changes.csv and changes.png say what changed since.\n"
    "--frames-every N also writes frames/NNNNNN.png (the overlay after scan N, 2N, ...) and,\n"
    "when ffmpeg is installed, timelapse.mp4.\n"
    "A ROS bag: sensor_msgs/LaserScan scans; odometry odom -> base_link from /tf (or\n"
    "nav_msgs/Odometry on --odom-topic), ground truth map -> base_link, the laser's mount\n"
    "base_link -> its frame from /tf_static; --poses fixed for a robot standing still.";

// --poses and --fixed-pose over the configuration's [input].
void applyPoseOptions(const po::variables_map& vm, MapConfig& config) {
  if (vm.count("poses")) {
    try {
      config.poses = parsePoseSource(vm["poses"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--poses: ") + e.what());
    }
  }
  if (vm.count("fixed-pose")) {
    try {
      config.fixed_pose = parseFixedPose(vm["fixed-pose"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--fixed-pose: ") + e.what());
    }
  }
}

po::options_description mapOptions() {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")(
      "input,i", po::value<std::string>()->required(),
      "the log to map (rawlog, simplemap, CARMEN, ROS bag)")(
      "config,c", po::value<std::string>(),
      "the .ini configuration (default: built-in defaults = config/default.ini)")(
      "out,o", po::value<std::string>()->default_value("out"), "output directory (created)")(
      "poses", po::value<std::string>(),
      "pose source: auto | simplemap | ground_truth | odometry | scan_matching "
      "(odometry corrected against the static map) | fixed (one pose for every scan: a "
      "robot standing still) | slam (a pose graph with loop closures estimated in a first "
      "pass); overrides [input] poses")(
      "fixed-pose", po::value<std::string>(),
      "\"X Y PHI\" [m m rad]: the pose of every scan with --poses fixed (default 0 0 0; "
      "overrides [input] fixed_pose)")(
      "no-baseline",
      "do not build the plain MRPT grid of the same scans (mrpt_plain.png and the\n"
      "comparison in summary.json); saves its time")(
      "prior", po::value<std::string>(),
      "an earlier run's output directory (or its session.json): continue that session and "
      "report what changed since (changes.csv, changes.png)")(
      "initial-pose", po::value<std::string>(),
      "\"X Y PHI\" [m m rad]: where the log's first scan was taken in the prior's map; every "
      "pose is moved rigidly to start there (with --prior)")(
      "frames-every", po::value<long>(),
      "write frames/NNNNNN.png every N scans (and timelapse.mp4 with ffmpeg)")(
      "verbose,v", "print progress and a summary even when not on a terminal");
  addBagOptions(opts, "ROS bag input: ");
  addCarmenOptions(opts, "CARMEN input: ");
  return opts;
}

}  // namespace

bool parseMapJob(const Args& args, MapJob& job, bool& verbose) {
  const po::options_description opts = mapOptions();
  po::variables_map vm;
  if (!parseArgs(args, opts, {}, vm, kMapUsage)) return false;
  if (vm.count("config"))
    job.config = MapConfig::load(IniFile::fromFile(vm["config"].as<std::string>()));
  applyPoseOptions(vm, job.config);
  job.bag = bagOptions(vm);
  job.input = vm["input"].as<std::string>();
  job.out_dir = vm["out"].as<std::string>();
  job.baseline = vm.count("no-baseline") == 0;
  if (vm.count("prior")) job.prior = vm["prior"].as<std::string>();
  if (vm.count("initial-pose")) {
    if (job.prior.empty()) throw UsageError("--initial-pose: only with --prior");
    try {
      job.initial_pose = parseFixedPose(vm["initial-pose"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--initial-pose: ") + e.what());
    }
  }
  verbose = vm.count("verbose") > 0;
  if (vm.count("frames-every")) {
    job.frames_every = vm["frames-every"].as<long>();
    if (job.frames_every < 1)
      throw UsageError("--frames-every: must be a positive number of scans");
  }
  // --carmen-odometry overrides [input] carmen_odometry.
  if (const auto odometry = carmenOptions(vm, job.carmen)) job.config.carmen_odometry = *odometry;
  return true;
}

namespace {

// The summary lines of a run on a terminal (or with --verbose).
void reportRun(const MapJob& job, const MapJobResult& r) {
  std::cerr << "dynamap map: " << r.counts.scans_used << " scans mapped from " << job.input << " ("
            << r.pose_source << " poses) in " << std::fixed << std::setprecision(2) << r.wall_s
            << " s; outputs in " << job.out_dir << "/\n";
  if (r.scan_matching) {
    const ScanMatchCounts& m = r.scan_match_counts;
    std::cerr << "dynamap map: scan matching corrected " << m.matched << " scans; "
              << m.fallbackTotal() << " kept their odometry pose (see summary.json)\n";
  }
  if (r.slam) {
    std::cerr << "dynamap map: slam: " << r.slam->loops_accepted << " loop closures accepted of "
              << r.slam->loops_proposed << " proposed; optimiser "
              << (r.slam->converged ? "converged" : "did not converge (front-end poses kept)")
              << "; pass 1 took " << r.slam_wall_s << " s\n";
  }
  if (r.baseline) {
    std::cerr << "dynamap map: plain MRPT grid of the same scans (" << r.baseline_wall_s
              << " s): " << r.baseline->plain_occupied_static_free
              << " cells it holds occupied are free in S (things that moved); "
              << r.baseline->static_occupied_plain_not << " cells S holds occupied it does not\n";
  }
}

// The signal that asked the run to stop (0: none). A handler may only set a flag: the run
// checks it after each scan and leaves the output directory as it was.
volatile std::sig_atomic_t g_stop_signal = 0;

void onStopSignal(int sig) {
  g_stop_signal = sig;
}

// SIGINT, SIGTERM and SIGHUP end the run cleanly; a second one of them acts at once (the
// handler is reset when it runs).
void catchStopSignals() {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

}  // namespace

// What the reader assumed, one line each; then one line for the records (lines, messages) that
// were not scans, one for the scans skipped (by reason, as in summary.json), one for timestamps
// that went backwards; last the fault the input ended in.
std::vector<std::string> mapWarnings(const MapJobResult& r) {
  std::vector<std::string> lines;
  for (const std::string& w : r.source_stats.warnings) lines.push_back(printable(w));
  const auto list = [](const std::map<std::string, std::size_t>& reasons, std::size_t& total) {
    std::string out;
    for (const auto& kv : reasons) {
      total += kv.second;
      out += (out.empty() ? "" : ", ") + kv.first + " (" + std::to_string(kv.second) + ")";
    }
    return out;
  };
  std::size_t records = 0, scans = 0;
  const std::string record_list = list(r.source_stats.skipped, records);
  const std::string scan_list = list(r.counts.scans_skipped, scans);
  const auto n = [](std::size_t v) { return std::to_string(v); };
  if (records > 0) {
    lines.push_back(n(records) + " " + r.source_stats.record_unit + " of " +
                    n(r.source_stats.records) + " skipped: " + printable(record_list) +
                    " (see summary.json)");
  }
  if (scans > 0) {
    lines.push_back(n(scans) + " scans of " + n(r.source_stats.scans) +
                    " skipped: " + printable(scan_list) + " (see summary.json)");
  }
  if (r.counts.time_backwards > 0) {
    lines.push_back(n(r.counts.time_backwards) +
                    " scans have a timestamp earlier than the scan before them (first: scan " +
                    n(r.counts.first_backwards_index) + ")");
  }
  if (!r.outcome.fault.empty()) {
    lines.push_back("input ended in a fault, outputs cover the scans before it: " +
                    printable(r.outcome.fault));
  }
  return lines;
}

int runMap(const Args& args) {
  MapJob job;
  bool verbose = false;
  if (!parseMapJob(args, job, verbose)) return kExitOk;
  const bool show = verbose || stderrIsTerminal();
  auto progress = std::make_unique<Progress>(show);
  job.progress = [&](double fraction, std::size_t scans) { progress->update(fraction, scans); };
  job.on_pass = [&](int pass) {  // pose source slam: a progress line for each pass
    progress->finish();
    progress = std::make_unique<Progress>(show);
    if (show && pass == 1) std::cerr << "dynamap map: pass 1 of 2: the trajectory (slam)\n";
    if (show && pass == 2) std::cerr << "dynamap map: pass 2 of 2: mapping on its poses\n";
  };
  catchStopSignals();
  job.cancelled = [] { return g_stop_signal != 0; };
  MapJobResult r;
  try {
    r = runMapJob(job);
  } catch (const RunCancelled&) {
    progress->finish();
    std::cerr << "dynamap map: interrupted by signal " << g_stop_signal << "; " << job.out_dir
              << " keeps the outputs it had\n";
    return 128 + g_stop_signal;
  }
  progress->finish();
  if (job.config.poses == PoseSource::Auto) {  // always: the user did not say which
    std::cerr << "dynamap map: poses auto: " << r.pose_source
              << (r.pose_detail.empty() ? "" : " (" + r.pose_detail + ")") << "\n";
  }
  if (r.start) {  // always: a pose the user may want to give next time, or to check
    std::fprintf(stderr,
                 "dynamap map: the log starts at %.3f %.3f %.4f in the prior's map (fit %.2f; "
                 "next best place %.2f)\n",
                 r.start->pose.x(), r.start->pose.y(), r.start->pose.phi(), r.start->score,
                 r.start->runner_up);
  }
  if (verbose || stderrIsTerminal()) reportRun(job, r);
  for (const std::string& w : mapWarnings(r)) std::cerr << "dynamap map: warning: " << w << "\n";
  return r.outcome.fault.empty() ? kExitOk : kExitPartialInput;
}

}  // namespace dynamap::app
