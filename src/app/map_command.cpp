// dynamap map: a log in, the static map, the dynamic map and their pictures out.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli.h"
#include "dynamap/base/ini.h"
#include "dynamap/input/open_source.h"
#include "dynamap/outputs/map_outputs.h"
#include "dynamap/outputs/render.h"
#include "dynamap/outputs/run_outputs.h"
#include "dynamap/outputs/tables.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap::app {
namespace {

const char* const kUsage =
    "usage: dynamap map --input FILE [--config FILE] [--out DIR] [--poses SOURCE]\n"
    "                   [--frames-every N] [--no-baseline] [--skip-bad-lines] [--fov DEG]\n"
    "                   [--verbose]\n\n"
    "Builds the static map S and the dynamic map D from a log (MRPT rawlog, MRPT simplemap or\n"
    "CARMEN log, plain or gz, told apart by content) and writes into DIR: static.png,\n"
    "dynamic.png, overlay.png, static.gridmap.gz and dynamic.gridmap.gz (MRPT),\n"
    "static.pgm + static.yaml (ROS map_server), config.ini (the effective configuration),\n"
    "summary.json, poses.txt (timestamp x y phi: the pose each scan was mapped at), the\n"
    "object table: objects.csv, events.csv, tracks.csv, and mrpt_plain.png:\n"
    "the plain MRPT grid of the same scans, compared with S in summary.json.\n"
    "--frames-every N also writes frames/NNNNNN.png (the overlay after scan N, 2N, ...) and,\n"
    "when ffmpeg is installed, timelapse.mp4.";

// The overlay as it is now, with the objects present now.
void writeFrame(const std::string& dir, const Mapper& mapper, std::size_t scan_index) {
  const auto& m = mapper.map();
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.png", scan_index);
  saveImageAtomically(renderOverlay(m, mapper.path(), &mapper.tracker().objects()), dir, name);
}

// Frames into timelapse.mp4 when ffmpeg is on PATH; a note on stderr otherwise.
void writeTimelapse(const std::string& out_dir, const std::string& frames_dir) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
    std::cerr << "dynamap map: ffmpeg not found, timelapse.mp4 skipped (frames are in "
              << frames_dir << "/)\n";
    return;
  }
  // Frames differ in size when the map grew: pad each to the last (largest) one's size.
  const std::string tmp = out_dir + "/.tmp-timelapse.mp4";
  const std::string cmd =
      "ffmpeg -loglevel error -y -framerate 10 -pattern_type glob -i '" + frames_dir +
      "/*.png' -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p '" + tmp +
      "' && mv '" + tmp + "' '" + out_dir + "/timelapse.mp4'";
  if (std::system(cmd.c_str()) != 0) {
    std::cerr << "dynamap map: warning: ffmpeg failed, timelapse.mp4 not written\n";
  }
}

// One line for the scans skipped (by reason, as in summary.json), one for timestamps that went
// backwards.
void warnAboutSkips(const RunCounts& counts, const SourceStats& stats, std::size_t backwards,
                    std::size_t first_backwards) {
  auto reasons = counts.scans_skipped;
  for (const auto& kv : stats.skipped) reasons[kv.first] += kv.second;
  std::size_t total = 0;
  std::string list;
  for (const auto& kv : reasons) {
    total += kv.second;
    list += (list.empty() ? "" : ", ") + kv.first + " (" + std::to_string(kv.second) + ")";
  }
  if (total > 0) {
    std::cerr << "dynamap map: warning: " << total << " scans skipped: " << list
              << " (see summary.json)\n";
  }
  if (backwards > 0) {
    std::cerr << "dynamap map: warning: " << backwards
              << " scans have a timestamp earlier than the scan before them (first: scan "
              << first_backwards << ")\n";
  }
}

}  // namespace

int runMap(const Args& args) {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")("input,i",
                                                      po::value<std::string>()->required(),
                                                      "the log to map (rawlog, simplemap, CARMEN)")(
      "config,c", po::value<std::string>(),
      "the .ini configuration (default: built-in defaults = config/default.ini)")(
      "out,o", po::value<std::string>()->default_value("out"), "output directory (created)")(
      "poses", po::value<std::string>(),
      "pose source: auto | simplemap | ground_truth | odometry | scan_matching\n"
      "(odometry corrected against the static map; overrides [input] poses)")(
      "no-baseline",
      "do not build the plain MRPT grid of the same scans (mrpt_plain.png and the\n"
      "comparison in summary.json); saves its time")(
      "skip-bad-lines",
      "CARMEN input: skip malformed lines (counted in summary.json) instead "
      "of stopping at the first")(
      "fov", po::value<double>(),
      "CARMEN input: field of view of every laser line [deg], overriding the log")(
      "frames-every", po::value<long>(),
      "write frames/NNNNNN.png every N scans (and timelapse.mp4 with ffmpeg)")(
      "verbose,v", "print progress and a summary even when not on a terminal");
  po::positional_options_description positional;
  po::variables_map vm;
  if (!parseArgs(args, opts, positional, vm, kUsage)) return kExitOk;

  MapConfig config;
  if (vm.count("config"))
    config = MapConfig::load(IniFile::fromFile(vm["config"].as<std::string>()));
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
  long frames_every = 0;
  if (vm.count("frames-every")) {
    frames_every = vm["frames-every"].as<long>();
    if (frames_every < 1) throw UsageError("--frames-every: must be a positive number of scans");
  }

  CarmenOptions carmen;
  carmen.skip_bad_lines = vm.count("skip-bad-lines") > 0;
  if (vm.count("fov")) {
    carmen.fov_deg = vm["fov"].as<double>();
    if (!(carmen.fov_deg > 0 && carmen.fov_deg <= 360))
      throw UsageError("--fov: must be in (0, 360] degrees");
  }

  prepareOutputDir(out_dir);  // before any work: an unwritable directory fails fast
  auto source = openScanSource(input, config.poses, &carmen);
  Mapper mapper(config);
  std::unique_ptr<PlainGrid> baseline;
  if (!vm.count("no-baseline"))
    baseline = std::make_unique<PlainGrid>(config.map, config.insertion);
  std::chrono::steady_clock::duration baseline_time{};
  Progress progress(verbose || stderrIsTerminal());
  TrackLog tracks(out_dir);  // streamed: rows are never kept in memory
  const std::string frames_dir = out_dir + "/frames";
  if (frames_every > 0) prepareOutputDir(frames_dir);

  // Scans stamped earlier than the one before them: counted in summary.json, warned about here.
  std::size_t backwards = 0, first_backwards = 0;
  bool have_t = false;
  double last_t = 0;

  const auto start = std::chrono::steady_clock::now();
  const InputOutcome outcome = runMapping(*source, mapper, [&](const ScanRecord& rec) {
    if (have_t && rec.t < last_t && backwards++ == 0) first_backwards = rec.index;
    have_t = true;
    last_t = rec.t;
    if (baseline) {  // timed on its own, so both runs' speeds can be reported
      const auto t0 = std::chrono::steady_clock::now();
      baseline->insert(*rec.scan, rec.pose);
      baseline_time += std::chrono::steady_clock::now() - t0;
    }
    tracks.append(rec.index, rec.t, mapper.tracker());
    if (frames_every > 0 && rec.index % static_cast<std::size_t>(frames_every) == 0) {
      writeFrame(frames_dir, mapper, rec.index);
    }
    progress.update(source->fractionRead(), mapper.counts().scans_used);
  });
  progress.finish();
  tracks.finish();
  const double baseline_s = std::chrono::duration<double>(baseline_time).count();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - baseline_s;

  writeMapOutputs(out_dir, mapper, *source, {input, wall_s, outcome, baseline.get(), baseline_s});
  if (frames_every > 0) writeTimelapse(out_dir, frames_dir);

  if (verbose || stderrIsTerminal()) {
    const auto& c = mapper.counts();
    std::cerr << "dynamap map: " << c.scans_used << " scans mapped from " << input << " ("
              << mapper.poseSourceName(*source) << " poses) in " << std::fixed
              << std::setprecision(2) << wall_s << " s; outputs in " << out_dir << "/\n";
    if (mapper.scanMatching()) {
      const ScanMatchCounts& m = mapper.scanMatchCounts();
      std::cerr << "dynamap map: scan matching corrected " << m.matched << " scans; "
                << m.fallbackTotal() << " kept their odometry pose (see summary.json)\n";
    }
    if (baseline) {
      const PlainComparison cmp = comparePlain(mapper.map(), baseline->grid());
      std::cerr << "dynamap map: plain MRPT grid of the same scans (" << baseline_s
                << " s): " << cmp.plain_occupied_static_free
                << " cells it holds occupied are free in S (things that moved); "
                << cmp.static_occupied_plain_not << " cells S holds occupied it does not\n";
    }
  }
  warnAboutSkips(mapper.counts(), source->stats(), backwards, first_backwards);
  if (!outcome.fault.empty()) {
    std::cerr << "dynamap map: warning: input ended in a fault, outputs cover the scans before "
                 "it: "
              << outcome.fault << "\n";
    return kExitPartialInput;
  }
  return kExitOk;
}

}  // namespace dynamap::app
