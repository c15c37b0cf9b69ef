// dynamap_bench_long: one long run, streamed. A simulated scenario of --scans scans (100,000 by
// default; generated here, scan by scan, never stored) goes through the same Mapper as
// `dynamap map`, objects on. Prints the peak resident memory, the memory after the first tenth,
// and the speed (scans/s of Mapper::process) over the first and the last tenth of the run: a run
// whose memory or time per scan grew with the number of scans would show it here.
//
// usage: dynamap_bench_long [--scans N] [--scale S]
// --scale S multiplies every length of the world by S (S = 2: four times the area). Run each
// scale in its own process (make bench-long does) so each peak memory is its own.

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include "dynamap/base/ini.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/sim/scenario.h"
#include "dynamap/sim/simulator.h"

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kScanRateHz = 10;

/// A 12 x 8 m hall (times `scale`) with two inner walls, a loop around them, six cylinders that
/// all move away early, then one move every 200 s, cycling the objects between two places each:
/// the map stops growing after the first lap while objects keep appearing and disappearing for
/// the whole run.
std::string scenarioText(std::size_t scans, double scale) {
  const double duration = static_cast<double>(scans) / kScanRateHz;
  std::ostringstream o;
  auto p = [&](double v) { return v * scale; };
  o << "[scenario]\nname = long\nduration_s = " << duration << "\nseed = 7\n\n[world]\n";
  const double W = p(6), H = p(4);
  o << "wall.1 = " << -W << ' ' << -H << ' ' << W << ' ' << -H << "\n"
    << "wall.2 = " << W << ' ' << -H << ' ' << W << ' ' << H << "\n"
    << "wall.3 = " << W << ' ' << H << ' ' << -W << ' ' << H << "\n"
    << "wall.4 = " << -W << ' ' << H << ' ' << -W << ' ' << -H << "\n"
    << "wall.5 = " << p(-2) << ' ' << p(-1) << ' ' << p(-2) << ' ' << p(1) << "\n"
    << "wall.6 = " << p(2) << ' ' << p(-1) << ' ' << p(2) << ' ' << p(1) << "\n\n";
  o << "[robot]\nwaypoints = " << p(-4) << ' ' << p(-2.5) << "  " << p(4) << ' ' << p(-2.5) << "  "
    << p(4) << ' ' << p(2.5) << "  " << p(-4) << ' ' << p(2.5) << "\n"
    << "loop = true\nspeed_mps = 0.5\nturn_rate_dps = 45\nscan_rate_hz = " << kScanRateHz
    << "\n\n[laser]\nbeams = 181\nfov_deg = 180\nmax_range_m = " << 8 * scale
    << "\nrange_noise_std_m = 0.01\nmount = 0 0 0\n\n"
    << "[odometry]\nnoise_xy_per_m = 0.02\nnoise_yaw_per_rad = 0.02\n\n[objects]\n";
  // Each object alternates between a home and an away place, all off the robot's route.
  const double home[6][2] = {{-5, -3.5}, {0, -3.5}, {5, -3.5}, {-5, 3.5}, {0, 3.5}, {5, 3.5}};
  const double away[6][2] = {{-4.5, 0}, {-1, 0}, {1, 0}, {4.5, 0}, {-3, 1.5}, {3, -1.5}};
  for (int i = 0; i < 6; ++i) {
    o << "object." << i + 1 << " = " << 0.2 + 0.1 * i << ' ' << p(home[i][0]) << ' '
      << p(home[i][1]) << "\n";
  }
  o << "\n[moves]\n";
  // Every object leaves home within the first 80 s, so that D holds all six from then on and
  // the first tenth of the run already does the work the last one does; then a move every 200 s.
  int n = 0;
  for (double t = 20; t + 10 < duration; t += n < 6 ? 10 : 200, ++n) {
    if (n == 6) t = 300;
    const int id = n % 6;
    const bool to_away = (n / 6) % 2 == 0;
    const double* q = to_away ? away[id] : home[id];
    o << "move." << n + 1 << " = " << t << ' ' << id + 1 << ' ' << p(q[0]) << ' ' << p(q[1])
      << " 3\n";
  }
  return o.str();
}

mrpt::obs::CObservation2DRangeScan::Ptr toScan(const dynamap::sim::Scenario& sc,
                                               const dynamap::sim::ScanTruth& st) {
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  scan->aperture = static_cast<float>(sc.laser.fov_deg * M_PI / 180);
  scan->rightToLeft = true;
  scan->maxRange = static_cast<float>(sc.laser.max_range_m);
  scan->resizeScan(st.ranges.size());
  for (std::size_t i = 0; i < st.ranges.size(); ++i) {
    scan->setScanRange(i, st.ranges[i]);
    scan->setScanRangeValidity(i, st.valid[i] != 0);
  }
  return scan;
}

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t scans = 100000;
  double scale = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--scans") {
      scans = std::strtoul(argv[i + 1], nullptr, 10);
    } else if (a == "--scale") {
      scale = std::strtod(argv[i + 1], nullptr);
    } else {
      std::cerr << "usage: dynamap_bench_long [--scans N] [--scale S]\n";
      return 2;
    }
  }
  if (scans < 10 || !(scale > 0)) {
    std::cerr << "dynamap_bench_long: --scans must be >= 10 and --scale > 0\n";
    return 2;
  }
  const auto scenario = dynamap::sim::parseScenario(
      dynamap::IniFile::fromText(scenarioText(scans, scale), "long.ini"), ".");
  dynamap::sim::Simulator sim(scenario);
  dynamap::MapConfig config;  // config/default.ini's values, objects on
  dynamap::Mapper mapper(config);

  const std::size_t total = std::min(scans, sim.scanCount());
  const std::size_t tenth = total / 10;
  double first_s = 0, last_s = 0, rss_after_first_tenth = 0;
  const auto start = Clock::now();
  dynamap::sim::ScanTruth st;
  dynamap::ScanRecord rec;
  for (std::size_t k = 0; k < total && sim.next(st); ++k) {
    rec.index = k;
    rec.t = st.t;
    rec.pose = mrpt::poses::CPose2D(st.pose.x, st.pose.y, st.pose.phi);
    rec.scan = toScan(scenario, st);
    const auto t0 = Clock::now();
    mapper.process(rec);
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    if (k < tenth) first_s += dt;
    if (k >= total - tenth) last_s += dt;
    if (k + 1 == tenth) rss_after_first_tenth = peakRssMiB();
  }
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  const auto& m = mapper.map();
  std::printf(
      "world %.0f x %.0f m (scale %g), %zu scans, %zu used, map %u x %u cells, %zu objects, "
      "%zu events\n",
      12 * scale, 8 * scale, scale, total, mapper.counts().scans_used, m.getSizeX(), m.getSizeY(),
      mapper.tracker().objects().size(), mapper.tracker().events().size());
  std::printf("peak RSS %.1f MiB (%.1f MiB after the first tenth)\n", peakRssMiB(),
              rss_after_first_tenth);
  std::printf("mapper scans/s: first tenth %.0f, last tenth %.0f (ratio last/first %.2f)\n",
              tenth / first_s, tenth / last_s, first_s / last_s);
  std::printf("whole run incl. simulation: %.1f s, %.0f scans/s\n", wall, total / wall);
  return 0;
}
