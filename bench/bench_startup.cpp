// dynamap_bench_startup: the fixed cost of a run, and how much of it is MRPT's.
//
// Runs three kinds of child process, alternately, --runs times each, and reports the median wall
// time (fork to exit) and the median peak resident memory (the kernel's ru_maxrss) of each:
//   mrpt_only  this program with --idle: it loads MRPT's map library (the grid dynamap is built
//              on, and every MRPT library that one needs) and exits at once
//   dynamap    `dynamap --help`: dynamap's libraries loaded, nothing done
//   map        `dynamap map --no-baseline` on --input with --config (the bundled tiny log)
// mrpt_only is the floor no program built on Debian's MRPT goes below: its shared libraries'
// pages and their static data are loaded before main() runs.
//
// usage: dynamap_bench_startup --dynamap BIN --input LOG --config INI [--runs N]

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_child.h"
#include "bench_stats.h"

namespace {

using dynamap::bench::ChildSample;
using dynamap::bench::median;
using dynamap::bench::runChild;

struct Options {
  std::string self, dynamap, input, config;
  int runs = 7;
};

bool parse(int argc, char** argv, Options& o) {
  o.self = argv[0];
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--dynamap") {
      o.dynamap = value;
    } else if (key == "--input") {
      o.input = value;
    } else if (key == "--config") {
      o.config = value;
    } else if (key == "--runs") {
      o.runs = std::max(1, std::atoi(value.c_str()));
    } else {
      return false;
    }
  }
  return argc % 2 == 1 && !o.dynamap.empty() && !o.input.empty() && !o.config.empty();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "--idle") == 0) {
    // A use of the library, so that the linker keeps it; never called.
    volatile auto keep = &mrpt::maps::COccupancyGridMap2D::GetRuntimeClassIdStatic;
    return keep == nullptr ? 1 : 0;
  }
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(
        stderr, "usage: dynamap_bench_startup --dynamap BIN --input LOG --config INI [--runs N]\n");
    return 2;
  }
  char dir_template[] = "/tmp/dynamap_bench_startup.XXXXXX";
  const char* dir = mkdtemp(dir_template);
  if (dir == nullptr) {
    std::perror("dynamap_bench_startup: mkdtemp");
    return 1;
  }
  const std::vector<std::pair<std::string, std::vector<std::string>>> kinds = {
      {"mrpt_only", {o.self, "--idle"}},
      {"dynamap", {o.dynamap, "--help"}},
      {"map",
       {o.dynamap, "map", "--no-baseline", "--poses", "ground_truth", "--config", o.config,
        "--input", o.input, "--out", std::string(dir) + "/out"}}};
  std::vector<std::vector<ChildSample>> samples(kinds.size());
  for (int r = 0; r < o.runs; ++r) {
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      ChildSample s;
      if (!runChild(kinds[k].second, s)) {
        std::fprintf(stderr, "dynamap_bench_startup: %s failed\n", kinds[k].second[0].c_str());
        std::filesystem::remove_all(dir);
        return 1;
      }
      samples[k].push_back(s);
    }
  }
  std::filesystem::remove_all(dir);
  std::printf("fixed cost, median of %d runs (wall time fork to exit, peak resident memory):\n",
              o.runs);
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    std::vector<double> wall;
    std::vector<long> peak;
    for (const ChildSample& s : samples[k]) wall.push_back(s.wall_s), peak.push_back(s.peak_kb);
    std::printf("  %-10s %6.3f s  %6.1f MB\n", kinds[k].first.c_str(), median(wall),
                static_cast<double>(median(peak)) / 1024.0);
  }
  return 0;
}
