// dynamap_bench_slam: what an odometry-only log costs, the whole `dynamap map --poses slam` run.
//
// The log's known poses (a CARMEN corrected log, a simulated rawlog's ground truth) are turned
// into drifting odometry once, by `dynamap perturb` with its default noise and --seed; then the
// odometry-only log is mapped --runs times with each front end, MRPT's point-to-point ICP (the
// default) and point-to-line ICP on S's cells ([scan_matching] point_to_line), alternately, each
// run in its own process (both passes, no plain MRPT grid beside it), and the median wall time,
// CPU time and peak resident memory of each are reported, with their ratio. The machine's speed
// varies from day to day: compare figures measured in the same session.
//
// usage: dynamap_bench_slam --dynamap BIN --input LOG [--runs N] [--seed S]

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_child.h"
#include "bench_stats.h"

namespace {

using dynamap::bench::ChildSample;
using dynamap::bench::median;
using dynamap::bench::runChild;

struct Options {
  std::string dynamap, input, seed = "1";
  int runs = 3;
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--dynamap") {
      o.dynamap = value;
    } else if (key == "--input") {
      o.input = value;
    } else if (key == "--runs") {
      o.runs = std::max(1, std::atoi(value.c_str()));
    } else if (key == "--seed") {
      o.seed = value;
    } else {
      return false;
    }
  }
  return argc % 2 == 1 && !o.dynamap.empty() && !o.input.empty();
}

/// The samples of each front end: [0] MRPT's ICP, [1] point-to-line.
using Samples = std::vector<ChildSample>[2];

/// Perturbs the log, then maps it `runs` times with each front end, alternately (a slow spell of
/// the machine costs both alike); false (and a message) when a child failed.
bool measure(const Options& o, const std::string& dir, Samples& samples) {
  ChildSample s;
  const std::string odometry = dir + "/perturbed";
  if (!runChild({o.dynamap, "perturb", "--input", o.input, "--out", odometry, "--seed", o.seed},
                s)) {
    std::fprintf(stderr, "dynamap_bench_slam: dynamap perturb failed on %s\n", o.input.c_str());
    return false;
  }
  const std::string ini[2] = {dir + "/icp.ini", dir + "/line.ini"};
  std::ofstream(ini[0]) << "[scan_matching]\npoint_to_line = false\n";
  std::ofstream(ini[1]) << "[scan_matching]\npoint_to_line = true\n";
  for (int r = 0; r < o.runs; ++r) {
    for (int k = 0; k < 2; ++k) {
      if (!runChild({o.dynamap, "map", "--poses", "slam", "--no-baseline", "--config", ini[k],
                     "--input", odometry + "/odometry.rawlog", "--out", dir + "/out"},
                    s)) {
        std::fprintf(stderr, "dynamap_bench_slam: dynamap map --poses slam failed\n");
        return false;
      }
      samples[k].push_back(s);
    }
  }
  return true;
}

/// Median wall and CPU time, fastest CPU time and median peak memory of one front end's runs;
/// returns the median CPU time.
double report(const char* name, const std::vector<ChildSample>& samples) {
  std::vector<double> wall, cpu;
  std::vector<long> peak;
  for (const ChildSample& s : samples) {
    wall.push_back(s.wall_s), cpu.push_back(s.cpu_s), peak.push_back(s.peak_kb);
  }
  std::printf("  %-14s wall %.2f s  CPU %.2f s (fastest %.2f s)  peak %.1f MB\n", name,
              median(wall), median(cpu), *std::min_element(cpu.begin(), cpu.end()),
              static_cast<double>(median(peak)) / 1024.0);
  return median(cpu);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: dynamap_bench_slam --dynamap BIN --input LOG [--runs N] [--seed S]\n");
    return 2;
  }
  char dir_template[] = "/tmp/dynamap_bench_slam.XXXXXX";
  const char* dir = mkdtemp(dir_template);
  if (dir == nullptr) {
    std::perror("dynamap_bench_slam: mkdtemp");
    return 1;
  }
  Samples samples;
  const bool ok = measure(o, dir, samples);
  std::filesystem::remove_all(dir);
  if (!ok) return 1;
  std::printf("slam, whole run on %s perturbed (seed %s), median of %d runs:\n", o.input.c_str(),
              o.seed.c_str(), o.runs);
  const double icp = report("MRPT ICP", samples[0]);
  const double line = report("point-to-line", samples[1]);
  std::printf("  CPU ratio MRPT ICP / point-to-line: %.2f\n", icp / line);
  return 0;
}
