// dynamap_bench: dynamap's speed against a plain MRPT COccupancyGridMap2D, on the same scans,
// poses, resolution and insertion options, in one process.
//
// The scans are loaded into memory first, so that only the work on them is timed. Three things
// are timed, alternately, and the median of the runs is reported:
//   mrpt      plain COccupancyGridMap2D insertion (one layer)
//   dynamap   DynamicGridMap insertion: S and D in one pass
//   pipeline  the whole per-scan step of `dynamap map` (Mapper::process: S and D, people, the
//             object table, the robot's path), outputs aside
// Times are the CPU time of the benchmark's thread, so that other work on the machine does not
// count against either side. All maps start at the same 20 x 20 m and grow as the scans need,
// as they do in a real run. Then each --read file is read once more, whole, to time its reader.
//
// usage: dynamap_bench [--input FILE] [--poses SOURCE] [--runs N] [--read FILE]...
// Ends with "ratio R" (dynamap's throughput / MRPT's) and "pipeline_ratio R" (the pipeline's).

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <string>
#include <vector>

#include "bench_stats.h"
#include "dynamap/input/open_source.h"
#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/pipeline/mapper.h"

namespace {

using dynamap::bench::median;

// The calling thread's CPU time [s].
double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Loaded {
  std::vector<dynamap::ScanRecord> records;
  std::vector<mrpt::poses::CPose3D> poses;
  std::size_t beams = 0;
};

Loaded load(const std::string& path, dynamap::PoseSource source) {
  Loaded l;
  auto src = dynamap::openScanSource(path, source);
  dynamap::ScanRecord rec;
  while (src->next(rec)) {
    l.records.push_back(rec);
    l.poses.emplace_back(rec.pose);
    l.beams = std::max(l.beams, rec.scan->getScanSize());
  }
  return l;
}

template <typename Map>
double timeInsertion(Map& map, const Loaded& l) {
  const double t0 = threadSeconds();
  for (std::size_t i = 0; i < l.records.size(); ++i) {
    map.insertObservation(*l.records[i].scan, l.poses[i]);
  }
  return threadSeconds() - t0;
}

double timePipeline(const Loaded& l) {
  dynamap::MapConfig config;  // the defaults of config/default.ini
  dynamap::Mapper mapper(config);
  const double t0 = threadSeconds();
  for (const dynamap::ScanRecord& rec : l.records) mapper.process(rec);
  return threadSeconds() - t0;
}

mrpt::maps::COccupancyGridMap2D plainGrid() {
  const dynamap::DynamicMapOptions opts;
  const dynamap::InsertionOptions ins;
  mrpt::maps::COccupancyGridMap2D plain(-10, 10, -10, 10, static_cast<float>(opts.resolution));
  plain.insertionOptions.maxDistanceInsertion = static_cast<float>(ins.max_distance_insertion);
  plain.insertionOptions.considerInvalidRangesAsFreeSpace = ins.invalid_ranges_as_free;
  plain.insertionOptions.horizontalTolerance =
      static_cast<float>(ins.horizontal_tolerance_deg * M_PI / 180.0);
  return plain;
}

void benchInsertion(const std::string& input, const Loaded& l, int runs) {
  std::vector<double> t_mrpt, t_dyn, t_pipe;
  for (int r = 0; r < runs; ++r) {
    mrpt::maps::COccupancyGridMap2D plain = plainGrid();
    t_mrpt.push_back(timeInsertion(plain, l));
    dynamap::DynamicGridMap dyn(dynamap::DynamicMapOptions{}, dynamap::InsertionOptions{}, -10,
                                10, -10, 10);
    t_dyn.push_back(timeInsertion(dyn, l));
    t_pipe.push_back(timePipeline(l));
  }
  const double n = static_cast<double>(l.records.size());
  const double mrpt_rate = n / median(t_mrpt);
  const double dyn_rate = n / median(t_dyn);
  const double pipe_rate = n / median(t_pipe);
  std::printf("input    %s\n", input.c_str());
  std::printf("scans    %zu (up to %zu beams), resolution %.3f m, %d runs each, median\n",
              l.records.size(), l.beams, dynamap::DynamicMapOptions{}.resolution, runs);
  std::printf("mrpt     %10.0f scans/s  (plain COccupancyGridMap2D)\n", mrpt_rate);
  std::printf("dynamap  %10.0f scans/s  (DynamicGridMap: S and D in one pass)\n", dyn_rate);
  std::printf("pipeline %10.0f scans/s  (the per-scan step: S, D, people, objects, path)\n",
              pipe_rate);
  std::printf("ratio %.3f\n", dyn_rate / mrpt_rate);
  std::printf("pipeline_ratio %.3f\n", pipe_rate / mrpt_rate);
}

// Reads `path` whole with dynamap's reader (poses as `poses`), once, and prints its speed.
void benchRead(const std::string& path, dynamap::PoseSource poses) {
  struct stat st {};
  const double mb = ::stat(path.c_str(), &st) == 0 ? static_cast<double>(st.st_size) / 1e6 : 0;
  const double t0 = threadSeconds();
  auto src = dynamap::openScanSource(path, poses);
  dynamap::ScanRecord rec;
  std::size_t scans = 0;
  while (src->next(rec)) ++scans;
  const double s = std::max(threadSeconds() - t0, 1e-9);
  std::printf("read     %8.1f MB/s %10.0f scans/s  %zu scans, %.1f MB  %s\n", mb / s,
              static_cast<double>(scans) / s, scans, mb, path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  std::string input = "/usr/share/mrpt/datasets/malaga-cs-fac-building.simplemap.gz";
  std::string poses = "auto";
  std::vector<std::string> reads;
  int runs = 7;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--input" && i + 1 < argc) {
      input = argv[++i];
    } else if (a == "--poses" && i + 1 < argc) {
      poses = argv[++i];
    } else if (a == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--read" && i + 1 < argc) {
      reads.emplace_back(argv[++i]);
    } else {
      std::cerr << "usage: dynamap_bench [--input FILE] [--poses SOURCE] [--runs N] "
                   "[--read FILE]...\n";
      return 2;
    }
  }
  try {
    const dynamap::PoseSource source = dynamap::parsePoseSource(poses);
    const Loaded l = load(input, source);
    if (l.records.empty()) {
      std::cerr << "dynamap_bench: no scans in " << input << "\n";
      return 1;
    }
    benchInsertion(input, l, runs);
    for (const std::string& r : reads) benchRead(r, dynamap::PoseSource::Auto);
  } catch (const std::exception& e) {
    std::cerr << "dynamap_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
