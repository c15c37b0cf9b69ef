// dynamap map: a log in, the static map, the dynamic map and their pictures out.

#include <chrono>
#include <iomanip>
#include <iostream>

#include "cli.h"
#include "dynamap/config_check.h"
#include "dynamap/map_outputs.h"
#include "dynamap/mapping_run.h"

namespace dynamap::app {
namespace {

const char* const kUsage =
    "usage: dynamap map --input FILE [--config FILE] [--out DIR] [--poses SOURCE] [--verbose]\n\n"
    "Builds the static map S and the dynamic map D from a log (MRPT rawlog, MRPT simplemap or\n"
    "CARMEN log, plain or gz, told apart by content) and writes into DIR: static.png,\n"
    "dynamic.png, overlay.png, static.gridmap.gz and dynamic.gridmap.gz (MRPT),\n"
    "static.pgm + static.yaml (ROS map_server), config.ini (the effective configuration)\n"
    "and summary.json.";

}  // namespace

int runMap(const Args& args) {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")(
      "input,i", po::value<std::string>()->required(), "the log to map (rawlog, simplemap, CARMEN)")(
      "config,c", po::value<std::string>(),
      "the .ini configuration (default: built-in defaults = config/default.ini)")(
      "out,o", po::value<std::string>()->default_value("out"), "output directory (created)")(
      "poses", po::value<std::string>(),
      "pose source: auto | simplemap | ground_truth | odometry (overrides [input] poses)")(
      "verbose,v", "print progress and a summary even when not on a terminal");
  po::positional_options_description positional;
  po::variables_map vm;
  if (!parseArgs(args, opts, positional, vm, kUsage)) return kExitOk;

  MapConfig config;
  if (vm.count("config")) config = MapConfig::load(IniFile::fromFile(vm["config"].as<std::string>()));
  if (vm.count("poses")) {
    try {
      config.poses = parsePoseSource(vm["poses"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--poses: ") + e.what());
    }
  }
  const std::string input = vm["input"].as<std::string>();
  const std::string out_dir = vm["out"].as<std::string>();
  const bool verbose = vm.count("verbose") > 0;

  prepareOutputDir(out_dir);  // before any work: an unwritable directory fails fast
  auto source = openScanSource(input, config.poses);
  Mapper mapper(config);
  Progress progress(verbose || stderrIsTerminal());

  const auto start = std::chrono::steady_clock::now();
  const InputOutcome outcome = runMapping(*source, mapper, [&](const ScanRecord&) {
    progress.update(source->fractionRead(), mapper.counts().scans_used);
  });
  progress.finish();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  writeMapOutputs(out_dir, mapper, *source, {input, wall_s, outcome});

  if (verbose || stderrIsTerminal()) {
    const auto& c = mapper.counts();
    std::cerr << "dynamap map: " << c.scans_used << " scans mapped from " << input << " ("
              << toString(source->poseSource()) << " poses) in " << std::fixed
              << std::setprecision(2) << wall_s << " s; outputs in " << out_dir << "/\n";
  }
  if (!outcome.fault.empty()) {
    std::cerr << "dynamap map: warning: input ended in a fault, outputs cover the scans before "
                 "it: "
              << outcome.fault << "\n";
    return kExitPartialInput;
  }
  return kExitOk;
}

}  // namespace dynamap::app
