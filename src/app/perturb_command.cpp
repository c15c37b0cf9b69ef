// dynamap perturb: a log with known poses turned into one whose odometry drifts like a wheel
// odometry's, with the known poses beside it as the truth: real scans to test pose estimation
// on (--poses slam) against the poses they were corrected to.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "commands.h"
#include "dynamap/input/open_source.h"
#include "dynamap/base/ini.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/random.h"

namespace dynamap::app {
namespace {

const char* const kPerturbUsage =
    "usage: dynamap perturb --input LOG --out DIR [--seed N] [--trans-noise F] [--rot-noise F]\n"
    "                       [--rot-per-m F] [--heading-bias F]\n"
    "       dynamap perturb --input LOG --out DIR --add-objects SPEC [--name NAME] [--config FILE]\n\n"
    "Reads a log with known poses (ground truth or a simplemap; a CARMEN corrected log's poses)\n"
    "and writes DIR/odometry.rawlog (gz): each scan with a CObservationOdometry whose increments\n"
    "are the true ones with noise (translation sd trans-noise x distance, heading sd rot-noise x\n"
    "turn + rot-per-m x distance, plus heading-bias x distance), DIR/gt.txt: the true pose of\n"
    "each scan (timestamp x y phi), and DIR/odometry.txt: the drifting odometry of each scan, the\n"
    "same way (dynamap eval --trajectory scores it). The same input and seed give the same bytes.\n\n"
    "With --add-objects, maps LOG first (S, with --config), then adds cylinders to its scans at\n"
    "places S holds free, away from walls and from the robot's path, and moves them while the\n"
    "robot looks elsewhere (jumps) or in view (glides), never to a place where the log's own\n"
    "beams end while the move is scored (a person of the log there); every beam that meets a\n"
    "cylinder before its own return is shortened to it (a beam without a return only where S\n"
    "holds its path free up to the cylinder). A move is dropped when the S of the edited scans\n"
    "does not hold its new place free as it is made (another cylinder stood there, unseen since).\n"
    "Writes DIR/NAME.rawlog (known poses)\n"
    "and the truth in the simulator's format (NAME.gt.txt, NAME.objects.csv, NAME.moves.csv),\n"
    "scored by `dynamap eval --truth DIR/NAME --result OUT`, NAME.own.csv: where the unedited\n"
    "log's run reported objects (the log's own changes), and NAME.added.txt: the moves dropped\n"
    "and why.\n"
    "SPEC is key=value,...: objects (4), moves (10), seed (1), sizes (0.2-0.6 m), glide (0 s:\n"
    "jumps), wall (0.15 m), path (0.5 m), seen (10 scans), beams (3 per scan), window (5 scans\n"
    "in eval's detection window).";

struct Noise {
  double trans = 0.03, rot = 0.03, rot_per_m = 0.005, heading_bias = 0.002;
};

/// The true increment `u` with odometry's error.
mrpt::poses::CPose2D noisyIncrement(const mrpt::poses::CPose2D& u, const Noise& n, sim::Rng& rng) {
  const double d = std::hypot(u.x(), u.y());
  const double x = u.x() + rng.gaussian(n.trans * d), y = u.y() + rng.gaussian(n.trans * d);
  const double phi =
      u.phi() + rng.gaussian(n.rot * std::abs(u.phi()) + n.rot_per_m * d) + n.heading_bias * d;
  return {x, y, phi};
}

double nonNegative(const po::variables_map& vm, const char* key, double fallback) {
  if (!vm.count(key)) return fallback;
  const double v = vm[key].as<double>();
  if (!(v >= 0 && v <= 1)) throw UsageError(std::string("--") + key + ": must be in [0, 1]");
  return v;
}

Noise noiseOf(const po::variables_map& vm) {
  Noise noise;
  noise.trans = nonNegative(vm, "trans-noise", noise.trans);
  noise.rot = nonNegative(vm, "rot-noise", noise.rot);
  noise.rot_per_m = nonNegative(vm, "rot-per-m", noise.rot_per_m);
  noise.heading_bias = nonNegative(vm, "heading-bias", noise.heading_bias);
  return noise;
}

void onlyWithAddObjects(const po::variables_map& vm) {
  for (const char* k : {"name", "config"}) {
    if (vm.count(k)) throw UsageError(std::string("--") + k + " goes with --add-objects");
  }
}

/// --add-objects: none of the odometry noise options, the seed in the spec.
int addObjects(const po::variables_map& vm) {
  for (const char* k : {"trans-noise", "rot-noise", "rot-per-m", "heading-bias"}) {
    if (vm.count(k)) throw UsageError(std::string("--") + k + " does not go with --add-objects");
  }
  if (!vm["seed"].defaulted()) throw UsageError("--seed: with --add-objects, give seed= in SPEC");
  MapConfig config;
  if (vm.count("config")) config = MapConfig::load(IniFile::fromFile(vm["config"].as<std::string>()));
  return runAddObjects(vm["input"].as<std::string>(), vm["out"].as<std::string>(),
                       vm["add-objects"].as<std::string>(),
                       vm.count("name") ? vm["name"].as<std::string>() : "", config);
}

}  // namespace

static po::options_description perturbOptions() {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")(
      "input,i", po::value<std::string>()->required(), "a log with known poses")(
      "out,o", po::value<std::string>()->required(), "output directory (created)")(
      "seed", po::value<unsigned long>()->default_value(1), "seed of the noise")(
      "trans-noise", po::value<double>(), "translation sd per metre (0.03)")(
      "rot-noise", po::value<double>(), "heading sd per radian turned (0.03)")(
      "rot-per-m", po::value<double>(), "heading sd per metre (0.005)")(
      "heading-bias", po::value<double>(), "heading bias per metre, radians (0.002)")(
      "add-objects", po::value<std::string>(), "add moving cylinders to the scans (see above)")(
      "name", po::value<std::string>(), "with --add-objects: the output files' name")(
      "config,c", po::value<std::string>(), "with --add-objects: the mapper's configuration");
  return opts;
}

int runPerturb(const Args& args) {
  const po::options_description opts = perturbOptions();
  po::positional_options_description positional;
  po::variables_map vm;
  if (!parseArgs(args, opts, positional, vm, kPerturbUsage)) return kExitOk;
  if (vm.count("add-objects")) return addObjects(vm);
  onlyWithAddObjects(vm);
  const Noise noise = noiseOf(vm);
  const std::string input = vm["input"].as<std::string>(), dir = vm["out"].as<std::string>();

  auto source = openScanSource(input, PoseSource::Auto);
  if (source->poseSource() == PoseSource::Odometry) {
    throw InputError(input + ": no known poses (ground truth or simplemap) to perturb");
  }
  prepareOutputDir(dir);
  const std::string rawlog_tmp = tempName(dir, "odometry.rawlog"), gt_tmp = tempName(dir, "gt.txt"),
                    odo_tmp = tempName(dir, "odometry.txt");
  mrpt::io::CFileGZOutputStream rawlog;
  if (!rawlog.open(rawlog_tmp)) throw InputError(rawlog_tmp + ": cannot write");
  std::FILE* gt = std::fopen(gt_tmp.c_str(), "w");
  if (!gt) throw InputError(gt_tmp + ": cannot write");
  std::FILE* odo_txt = std::fopen(odo_tmp.c_str(), "w");
  if (!odo_txt) {
    std::fclose(gt);
    throw InputError(odo_tmp + ": cannot write");
  }
  sim::Rng rng(vm["seed"].as<unsigned long>());
  ScanRecord rec;
  mrpt::poses::CPose2D last_true, odometry;
  std::size_t n = 0;
  auto arch = mrpt::serialization::archiveFrom(rawlog);
  while (source->next(rec)) {  // a fault in the input is an error: no partial output
    // Both start at the first true pose.
    odometry = n > 0 ? odometry + noisyIncrement(rec.pose - last_true, noise, rng) : rec.pose;
    last_true = rec.pose;
    mrpt::obs::CObservationOdometry odo;
    odo.sensorLabel = "ODOMETRY";
    odo.timestamp = mrpt::Clock::fromDouble(rec.t);  // the rawlog reader's time of the scan
    rec.scan->timestamp = odo.timestamp;
    odo.odometry = odometry;
    arch << odo << *rec.scan;
    std::fprintf(gt, "%.6f %.6f %.6f %.6f\n", rec.t, rec.pose.x(), rec.pose.y(), rec.pose.phi());
    std::fprintf(odo_txt, "%.6f %.6f %.6f %.6f\n", rec.t, odometry.x(), odometry.y(),
                 odometry.phi());
    ++n;
  }
  rawlog.close();
  const bool gt_ok = std::fclose(gt) == 0, odo_ok = std::fclose(odo_txt) == 0;
  if (!gt_ok) throw InputError(gt_tmp + ": write error");
  if (!odo_ok) throw InputError(odo_tmp + ": write error");
  if (n == 0) throw InputError(input + ": no scans");
  commit(rawlog_tmp, dir, "odometry.rawlog");
  commit(gt_tmp, dir, "gt.txt");
  commit(odo_tmp, dir, "odometry.txt");
  std::cout << "dynamap perturb: " << n << " scans of " << input << " -> " << dir
            << "/odometry.rawlog, true poses in " << dir << "/gt.txt, the odometry in " << dir
            << "/odometry.txt\n";
  return kExitOk;
}

}  // namespace dynamap::app
