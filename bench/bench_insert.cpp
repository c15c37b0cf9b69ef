// dynamap_bench: insertion speed of dynamap's DynamicGridMap against a plain MRPT
// COccupancyGridMap2D, on the same scans, poses, resolution and insertion options, in one
// process. The scans are loaded into memory first so only insertion is timed; the two maps are
// timed alternately, and the median of the runs is reported. Times are the CPU time of the
// benchmark's thread, so that other work on the machine does not count against either map.
// Both maps start at the same 20 x 20 m and grow as the scans need, as they do in a real run.
//
// usage: dynamap_bench [--input FILE] [--poses SOURCE] [--runs N]
// Prints scans/s for each and ends with "ratio R", R = dynamap's throughput / MRPT's.

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "dynamap/input/open_source.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace {

// The calling thread's CPU time [s].
double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Loaded {
  std::vector<mrpt::obs::CObservation2DRangeScan::Ptr> scans;
  std::vector<mrpt::poses::CPose3D> poses;
  std::size_t beams = 0;
};

Loaded load(const std::string& path, dynamap::PoseSource source) {
  Loaded l;
  auto src = dynamap::openScanSource(path, source);
  dynamap::ScanRecord rec;
  while (src->next(rec)) {
    l.scans.push_back(rec.scan);
    l.poses.emplace_back(rec.pose);
    l.beams = std::max(l.beams, rec.scan->getScanSize());
  }
  return l;
}

template <typename Map>
double timeInsertion(Map& map, const Loaded& l) {
  const double t0 = threadSeconds();
  for (std::size_t i = 0; i < l.scans.size(); ++i) map.insertObservation(*l.scans[i], l.poses[i]);
  return threadSeconds() - t0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string input = "/usr/share/mrpt/datasets/malaga-cs-fac-building.simplemap.gz";
  std::string poses = "auto";
  int runs = 7;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--input" && i + 1 < argc) {
      input = argv[++i];
    } else if (a == "--poses" && i + 1 < argc) {
      poses = argv[++i];
    } else if (a == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else {
      std::cerr << "usage: dynamap_bench [--input FILE] [--poses SOURCE] [--runs N]\n";
      return 2;
    }
  }
  try {
    const Loaded l = load(input, dynamap::parsePoseSource(poses));
    if (l.scans.empty()) {
      std::cerr << "dynamap_bench: no scans in " << input << "\n";
      return 1;
    }
    const dynamap::DynamicMapOptions opts;  // the defaults of config/default.ini
    const dynamap::InsertionOptions ins;
    const float res = static_cast<float>(opts.resolution);
    std::vector<double> t_mrpt, t_dyn;
    for (int r = 0; r < runs; ++r) {
      mrpt::maps::COccupancyGridMap2D plain(-10, 10, -10, 10, res);
      plain.insertionOptions.maxDistanceInsertion = static_cast<float>(ins.max_distance_insertion);
      plain.insertionOptions.considerInvalidRangesAsFreeSpace = ins.invalid_ranges_as_free;
      plain.insertionOptions.horizontalTolerance =
          static_cast<float>(ins.horizontal_tolerance_deg * M_PI / 180.0);
      t_mrpt.push_back(timeInsertion(plain, l));
      dynamap::DynamicGridMap dyn(opts, ins, -10, 10, -10, 10);
      t_dyn.push_back(timeInsertion(dyn, l));
    }
    const double n = static_cast<double>(l.scans.size());
    const double mrpt_rate = n / median(t_mrpt);
    const double dyn_rate = n / median(t_dyn);
    std::printf("input    %s\n", input.c_str());
    std::printf("scans    %zu (up to %zu beams), resolution %.3f m, %d runs each, median\n",
                l.scans.size(), l.beams, opts.resolution, runs);
    std::printf("mrpt     %10.0f scans/s  (plain COccupancyGridMap2D)\n", mrpt_rate);
    std::printf("dynamap  %10.0f scans/s  (DynamicGridMap: S and D in one pass)\n", dyn_rate);
    std::printf("ratio %.3f\n", dyn_rate / mrpt_rate);
  } catch (const std::exception& e) {
    std::cerr << "dynamap_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
