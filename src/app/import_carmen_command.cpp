// dynamap import-carmen: a CARMEN log to an MRPT rawlog (observations only, gz) that keeps every
// scan's own timestamp, plus the companion <out>.gt.txt of ground-truth poses.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <boost/program_options.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "cli.h"
#include "dynamap/input/carmen_reader.h"
#include "import_output.h"

namespace dynamap::app {

namespace {

namespace po = boost::program_options;

struct ImportArgs {
  std::string input, output;
  CarmenOptions carmen;
};

po::options_description importOptions() {
  po::options_description o("dynamap import-carmen IN.log[.gz] --out OUT.rawlog [options]");
  o.add_options()                             //
      ("help,h", "print this help and exit")  //
      ("out,o", po::value<std::string>(),
       "the MRPT rawlog to write (observations only, gz-compressed). Its ground truth goes to "
       "<OUT without .rawlog>.gt.txt, one 'timestamp x y phi' line per scan");
  addCarmenOptions(o, "");
  return o;
}

ImportArgs parseImportArgs(const Args& args, bool& help) {
  po::options_description visible = importOptions();
  po::variables_map vm;
  ImportArgs a;
  help = !parseImportCommand(
      args, visible,
      "Reads FLASER/RLASER, ROBOTLASER1, ODOM and the laser PARAM lines of a CARMEN log\n"
      "(plain or gz); every scan keeps the log's own time (its ipc_timestamp).\n"
      "Writes, per laser line: CObservationOdometry (label ODOMETRY, when known; with\n"
      "--carmen-odometry odom per ODOM line instead), CObservation2DRangeScan (LASER),\n"
      "CObservationRobotPose (GT, the line's pose). Other lines are skipped and counted.\n"
      "See docs/inputs.md (CARMEN logs).\n",
      "CARMEN log", vm, a.input, a.output);
  if (help) return {};
  // The stream written as CObservationOdometry (laser unless --carmen-odometry says odom).
  if (const auto odometry = carmenOptions(vm, a.carmen)) a.carmen.odometry = *odometry;
  return a;
}

mrpt::obs::CObservationOdometry odometryObservation(const CarmenEvent& e) {
  mrpt::obs::CObservationOdometry odo = odometryAt(e.t, *e.odometry);
  if (e.kind == CarmenEvent::Kind::Odometry) {
    odo.hasVelocities = true;
    odo.velocityLocal = mrpt::math::TTwist2D(e.tv, 0, e.rv);
  }
  return odo;
}

mrpt::obs::CObservationRobotPose groundTruthObservation(const CarmenEvent& e) {
  return groundTruthAt(e.t, e.pose);
}

/// What the summary reports beyond the reader's own counts.
struct ImportTally {
  std::size_t odometry = 0;
  std::optional<double> t_first, t_last;
  std::size_t beams = 0;
  double aperture_deg = 0;
};

void printSummary(const ImportArgs& a, const SourceStats& s, const ImportTally& tally,
                  const std::string& gt_file) {
  std::cout << "import-carmen: " << a.input << "\n"
            << "  lines read:  " << s.records << "\n"
            << "  scans:       " << s.scans << " (the first: " << tally.beams << " beams, "
            << tally.aperture_deg / (tally.beams - 1) << " deg apart, aperture "
            << tally.aperture_deg << " deg)\n"
            << "  odometry:    " << tally.odometry << " ODOM lines; written: "
            << (a.carmen.odometry == CarmenOdometrySource::OdomLines
                    ? "the ODOM lines"
                    : "each laser line's odometry fields")
            << "\n";
  if (tally.t_first) {
    char span[128];
    std::snprintf(span, sizeof span, "%.6f .. %.6f (%.1f s)", *tally.t_first, *tally.t_last,
                  *tally.t_last - *tally.t_first);
    std::cout << "  time:        " << span << "\n";
  }
  const auto bad = s.skipped.find("bad line");
  std::cout << "  bad lines:   " << (bad == s.skipped.end() ? 0 : bad->second) << "\n";
  for (const auto& [reason, n] : s.skipped) {
    if (reason != "bad line") std::cout << "  skipped:     " << n << " " << reason << " (lines)\n";
  }
  for (const std::string& w : s.warnings) std::cout << "  warning:     " << w << "\n";
  std::cout << "wrote " << a.output << " and " << gt_file << "\n";
}

}  // namespace

int runImportCarmen(const Args& args) {
  bool help = false;
  const ImportArgs a = parseImportArgs(args, help);
  if (help) return kExitOk;

  CarmenReader reader(a.input, a.carmen);
  ImportOutput out(a.input, a.output);
  ImportTally tally;
  CarmenEvent e;
  while (reader.next(e)) {
    // One odometry stream, the one asked for: two interleaved would be one noisy stream.
    const bool odom_lines = a.carmen.odometry == CarmenOdometrySource::OdomLines;
    if (e.kind == CarmenEvent::Kind::Odometry) {
      if (odom_lines) out.write(odometryObservation(e));
      ++tally.odometry;
      continue;
    }
    if (!tally.t_first) {
      tally.t_first = e.t;
      tally.beams = e.scan->getScanSize();
      tally.aperture_deg = e.scan->aperture * 180.0 / M_PI;
    }
    tally.t_last = e.t;
    if (e.odometry && !odom_lines) out.write(odometryObservation(e));
    out.write(*e.scan);
    out.write(groundTruthObservation(e));
    out.writeGroundTruth(e.t, e.pose);
  }
  if (reader.stats().scans == 0) {
    throw InputError(a.input + ": no laser lines (FLASER, RLASER, ROBOTLASER1) in the log");
  }
  out.commit();
  printSummary(a, reader.stats(), tally, out.groundTruthFile());
  return kExitOk;
}

}  // namespace dynamap::app
