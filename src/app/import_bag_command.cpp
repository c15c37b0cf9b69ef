// dynamap import-bag: a ROS 1 bag to an MRPT rawlog (observations only, gz) that keeps every
// scan's own header stamp, plus the companion <out>.gt.txt of ground-truth poses when the bag
// has a ground-truth frame.

#include <boost/program_options.hpp>

#include <cstdio>
#include <iostream>
#include <optional>

#include "cli.h"
#include "dynamap/input/bag_source.h"
#include "import_output.h"

namespace dynamap::app {

#ifdef DYNAMAP_HAVE_ROSBAG

namespace {

namespace po = boost::program_options;

struct BagImportArgs {
  std::string input, output;
  BagOptions bag;
};

po::options_description bagImportOptions() {
  po::options_description o("dynamap import-bag IN.bag --out OUT.rawlog [options]");
  o.add_options()                             //
      ("help,h", "print this help and exit")  //
      ("out,o", po::value<std::string>(),
       "the MRPT rawlog to write (observations only, gz-compressed). Ground truth, when the bag "
       "has it, goes to <OUT without .rawlog>.gt.txt, one 'timestamp x y phi' line per scan");
  addBagOptions(o, "");
  return o;
}

BagImportArgs parseBagImportArgs(const Args& args, bool& help) {
  po::options_description visible = bagImportOptions();
  po::variables_map vm;
  BagImportArgs a;
  help = !parseImportCommand(
      args, visible,
      "Reads sensor_msgs/LaserScan, /tf, /tf_static and nav_msgs/Odometry with ROS's\n"
      "rosbag library; every scan keeps its header stamp and frame (sensorLabel).\n"
      "Writes, per scan: CObservationOdometry (label ODOMETRY, when the bag has\n"
      "odometry), CObservation2DRangeScan (sensorPose: the mount from /tf),\n"
      "CObservationRobotPose (GT, when the bag has the ground-truth frame).\n"
      "Scans without the poses the bag offers are skipped and counted.\n",
      "ROS bag", vm, a.input, a.output);
  if (help) return {};
  a.bag = bagOptions(vm);
  return a;
}

void printBagSummary(const BagImportArgs& a, const BagReader& reader, std::size_t written,
                     std::optional<double> t_first, double t_last, bool gt) {
  const SourceStats& s = reader.stats();
  const BagContents& c = reader.contents();
  std::cout << "import-bag: " << a.input << "\n"
            << "  messages read: " << s.records << "\n"
            << "  scans:         " << s.scans << " on " << c.scan_topic << ", " << written
            << " written\n"
            << "  odometry:      " << (c.odometry ? "yes" : "none") << "\n"
            << "  ground truth:  " << (gt ? "frame " + a.bag.gt_frame : std::string("none"))
            << "\n";
  if (t_first) {
    char span[128];
    std::snprintf(span, sizeof span, "%.6f .. %.6f (%.1f s)", *t_first, t_last, t_last - *t_first);
    std::cout << "  time:          " << span << "\n";
  }
  for (const auto& [reason, n] : s.skipped)
    std::cout << "  skipped:       " << n << " " << reason << "\n";
  std::cout << "wrote " << a.output << (gt ? " and " + groundTruthPath(a.output) : "") << "\n";
}

}  // namespace

int runImportBag(const Args& args) {
  bool help = false;
  const BagImportArgs a = parseBagImportArgs(args, help);
  if (help) return kExitOk;

  BagReader reader(a.input, a.bag);
  const bool odometry = reader.contents().odometry, gt = reader.contents().ground_truth;
  reader.require(odometry, gt);
  ImportOutput out(a.input, a.output, gt);
  std::size_t written = 0;
  std::optional<double> t_first;
  double t_last = 0;
  BagScan s;
  std::string fault;
  try {
    while (reader.next(s)) {
      if (!t_first) t_first = s.t;
      t_last = s.t;
      if (s.odometry) out.write(odometryAt(s.t, *s.odometry));
      out.write(*s.scan);
      if (s.ground_truth) {
        out.write(groundTruthAt(s.t, *s.ground_truth));
        out.writeGroundTruth(s.t, *s.ground_truth);
      }
      ++written;
    }
  } catch (const InputError& e) {
    fault = e.what();  // the scans before it are written: a rawlog of the good part
  }
  if (written == 0) {
    throw InputError(fault.empty() ? a.input + ": no scan with " +
                                         (gt         ? "ground truth"
                                          : odometry ? "odometry"
                                                     : "a mount")
                                   : fault);
  }
  out.commit();
  printBagSummary(a, reader, written, t_first, t_last, gt);
  if (!fault.empty()) {
    std::cerr << "dynamap import-bag: warning: the bag ended in a fault; the rawlog holds the "
                 "scans before it: "
              << fault << "\n";
    return kExitPartialInput;
  }
  return kExitOk;
}

#else  // a build without rosbag (-DDYNAMAP_ROSBAG=OFF)

int runImportBag(const Args&) {
  throw InputError(
      "this dynamap was built without ROS bag support (-DDYNAMAP_ROSBAG=OFF); rebuild with "
      "-DDYNAMAP_ROSBAG=ON");
}

#endif

}  // namespace dynamap::app
