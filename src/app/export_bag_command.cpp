// dynamap export-bag: any log dynamap reads (rawlog, CARMEN, ROS 1 bag, ROS 2 bag) as a ROS 2
// bag, MCAP or .db3, with the messages a ROS 2 robot records: sensor_msgs/msg/LaserScan on
// /scan, the laser's mount on /tf_static (base_link -> laser) and the poses on /tf (map ->
// base_link for ground truth, odom -> base_link for odometry). Mapped, the bag gives the map of
// the log it came from.

#include <boost/program_options.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>

#include "cli.h"
#include "dynamap/input/open_source.h"

#ifdef DYNAMAP_HAVE_ROSBAG
#include "dynamap/input/cdr_messages.h"
#include "dynamap/input/ros2_writer.h"
#endif

namespace dynamap::app {

#ifdef DYNAMAP_HAVE_ROSBAG

namespace {

namespace po = boost::program_options;
using mrpt::poses::CPose2D;

struct ExportArgs {
  std::string input, output, compression;
  InputOptions in;
};

po::options_description exportOptions() {
  po::options_description o("dynamap export-bag IN --out OUT.mcap|OUT.db3 [options]");
  o.add_options()                             //
      ("help,h", "print this help and exit")  //
      ("out,o", po::value<std::string>(),
       "the ROS 2 bag to write: an MCAP file (.mcap) or a "
       "rosbag2 SQLite file (.db3)")  //
      ("compression", po::value<std::string>()->default_value("zstd"),
       "MCAP chunks: zstd, lz4 or none")  //
      ("poses", po::value<std::string>()->default_value("auto"),
       "the poses written to /tf, as dynamap map --poses reads the log: auto, ground_truth "
       "(map -> base_link), odometry (odom -> base_link) or fixed (no /tf)");
  addBagOptions(o, "a ROS bag input: ");
  return o;
}

ExportArgs parseExportArgs(const Args& args, bool& help) {
  po::options_description visible = exportOptions();
  po::variables_map vm;
  ExportArgs a;
  help = !parseImportCommand(
      args, visible,
      "Writes every scan of the log as a sensor_msgs/msg/LaserScan on /scan (frame laser,\n"
      "stamped with the scan's time, beams the log's invalid as +inf), its mount once on\n"
      "/tf_static (base_link -> laser; another mount, another frame laser_1, ...) and its pose\n"
      "on /tf at the same stamp. dynamap map reads the bag back as it read the log.\n",
      "log", vm, a.input, a.output);
  if (help) return {};
  a.compression = vm["compression"].as<std::string>();
  try {
    a.in.poses = parsePoseSource(vm["poses"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (a.in.poses != PoseSource::Auto && a.in.poses != PoseSource::GroundTruth &&
      a.in.poses != PoseSource::Odometry && a.in.poses != PoseSource::Fixed) {
    throw UsageError("--poses: auto, ground_truth, odometry or fixed");
  }
  a.in.bag = bagOptions(vm);
  return a;
}

ros::Time stamp(double t) {
  if (!(t >= 0) || t > std::numeric_limits<std::int32_t>::max()) {
    throw InputError("a scan time of " + std::to_string(t) + " s has no ROS 2 stamp");
  }
  return ros::Time(t);
}

/// The yaw the bag reader takes from a rotation about z (bag_source.cpp's yawOf, x = y = 0).
double readYaw(double z, double w) {
  return std::atan2(2.0 * (w * z + 0.0 * 0.0), 1.0 - 2.0 * (0.0 * 0.0 + z * z));
}

/// A rotation by `yaw` about z whose yaw reads back as `yaw` bit for bit: (sin, cos) of yaw/2
/// moved by a few units in the last place when they alone read back one off (1 yaw in 5).
/// A pose then crosses the bag unchanged, and so does the map made from it.
geometry_msgs::Quaternion exactRotation(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2);
  q.w = std::cos(yaw / 2);
  constexpr int kUlps = 16;
  for (int dz = 0; dz <= 2 * kUlps; ++dz) {
    double z = q.z;
    for (int i = 0; i < (dz + 1) / 2; ++i) z = std::nextafter(z, dz % 2 ? 2.0 : -2.0);
    for (int dw = 0; dw <= 2 * kUlps; ++dw) {
      double w = q.w;
      for (int i = 0; i < (dw + 1) / 2; ++i) w = std::nextafter(w, dw % 2 ? 2.0 : -2.0);
      if (readYaw(z, w) == yaw) {
        q.z = z;
        q.w = w;
        return q;
      }
    }
  }
  return q;  // none within kUlps: the nearest rotation, one unit in the last place off at most
}

geometry_msgs::TransformStamped transform(double t, const std::string& parent,
                                          const std::string& child, const CPose2D& p) {
  geometry_msgs::TransformStamped tr;
  tr.header.stamp = stamp(t);
  tr.header.frame_id = parent;
  tr.child_frame_id = child;
  tr.transform.translation.x = p.x();
  tr.transform.translation.y = p.y();
  tr.transform.rotation = exactRotation(p.phi());
  return tr;
}

/// Where the bag reader puts the middle beam of `m`: float32 angles rarely make a symmetric scan
/// exactly symmetric (180 degrees in 361 beams: -5.6e-8 rad off), so the mount written takes it
/// out again.
double readCentre(const sensor_msgs::LaserScan& m) {
  const std::size_t n = m.ranges.size();
  return m.angle_min + double(m.angle_increment) * static_cast<double>(n > 0 ? n - 1 : 0) / 2;
}

/// A scan as the LaserScan it reads back as: beams from -aperture/2 (clockwise scans mirrored
/// by a negative increment), invalid beams +inf.
sensor_msgs::LaserScan laserScan(const mrpt::obs::CObservation2DRangeScan& scan, double t,
                                 const std::string& frame) {
  sensor_msgs::LaserScan m;
  m.header.stamp = stamp(t);
  m.header.frame_id = frame;
  const std::size_t n = scan.getScanSize();
  const float step = n > 1 ? scan.aperture / static_cast<float>(n - 1) : 0.0f;
  m.angle_min = scan.rightToLeft ? -scan.aperture / 2 : scan.aperture / 2;
  m.angle_increment = scan.rightToLeft ? step : -step;
  m.angle_max = m.angle_min + m.angle_increment * static_cast<float>(n > 0 ? n - 1 : 0);
  m.range_min = 0.0f;
  m.range_max = scan.maxRange;
  m.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    m.ranges[i] = scan.getScanRangeValidity(i) ? scan.getScanRange(i)
                                               : std::numeric_limits<float>::infinity();
  }
  return m;
}

struct ExportCounts {
  std::size_t scans = 0, mounts = 0;
};

ExportCounts exportScans(ScanSource& source, ros2::BagWriter& bag) {
  const bool gt = source.poseSource() == PoseSource::GroundTruth;
  const std::string fixed = gt ? "map" : "odom";
  const bool posed = source.poseSource() != PoseSource::Fixed;
  std::map<std::tuple<double, double, double>, std::string> mounts;
  // A recorder's time only goes forward: a scan stamped before the one before it (Intel has 4)
  // is recorded at the same time as that one, so the bag keeps the log's order.
  std::uint64_t recorded = 0;
  const auto ns = [&recorded](double t) {
    recorded = std::max(recorded, static_cast<std::uint64_t>(stamp(t).toNSec()));
    return recorded;
  };
  ExportCounts n;
  ScanRecord r;
  while (source.next(r)) {
    const CPose2D p(r.scan->sensorPose);
    sensor_msgs::LaserScan scan = laserScan(*r.scan, r.t, "");
    const CPose2D mount(p.x(), p.y(), p.phi() - readCentre(scan));
    auto it = mounts.find({mount.x(), mount.y(), mount.phi()});
    if (it == mounts.end()) {
      const std::string frame = mounts.empty() ? "laser" : "laser_" + std::to_string(mounts.size());
      it = mounts.emplace(std::make_tuple(mount.x(), mount.y(), mount.phi()), frame).first;
      tf2_msgs::TFMessage s;
      s.transforms.push_back(transform(r.t, "base_link", frame, mount));
      bag.write("/tf_static", "tf2_msgs/msg/TFMessage", ns(r.t), ros2::encode(s));
    }
    scan.header.frame_id = it->second;
    if (posed) {
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(transform(r.t, fixed, "base_link", r.pose));
      bag.write("/tf", "tf2_msgs/msg/TFMessage", ns(r.t), ros2::encode(tf));
    }
    bag.write("/scan", "sensor_msgs/msg/LaserScan", ns(r.t), ros2::encode(scan));
    ++n.scans;
  }
  n.mounts = mounts.size();
  return n;
}

}  // namespace

int runExportBag(const Args& args) {
  bool help = false;
  const ExportArgs a = parseExportArgs(args, help);
  if (help) return kExitOk;
  auto source = openScanSource(a.input, a.in);
  std::unique_ptr<ros2::BagWriter> bag;
  try {
    bag = std::make_unique<ros2::BagWriter>(a.output, a.compression);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  ExportCounts n;
  std::string fault;
  try {
    n = exportScans(*source, *bag);
  } catch (const InputError& e) {
    fault = e.what();  // the scans before it are written: a bag of the good part
  }
  bag->close();
  std::cout << "export-bag: " << a.input << "\n"
            << "  scans:  " << n.scans << " on /scan, " << n.mounts << " laser mount(s)\n"
            << "  poses:  " << toString(source->poseSource()) << "\n"
            << "wrote " << a.output << "\n";
  if (!fault.empty()) {
    std::cerr << "dynamap export-bag: warning: the log ended in a fault; the bag holds the scans "
                 "before it: "
              << fault << "\n";
    return kExitPartialInput;
  }
  return kExitOk;
}

#else  // a build without ROS bag support (-DDYNAMAP_ROSBAG=OFF)

int runExportBag(const Args&) {
  throw InputError(
      "this dynamap was built without ROS bag support (-DDYNAMAP_ROSBAG=OFF); rebuild with "
      "-DDYNAMAP_ROSBAG=ON");
}

#endif

}  // namespace dynamap::app
