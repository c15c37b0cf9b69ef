#include "cli.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace dynamap::app {

bool parseArgs(const Args& args, const po::options_description& options,
               const po::positional_options_description& positional, po::variables_map& vm,
               const std::string& usage) {
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), vm);
    if (vm.count("help")) {
      std::cout << usage << "\n\n" << options << "\n";
      return false;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(e.what());
  }
  return true;
}

bool parseImportCommand(const Args& args, const po::options_description& visible,
                        const std::string& help_text, const std::string& what,
                        po::variables_map& vm, std::string& input, std::string& output) {
  po::options_description all = visible;
  all.add_options()("input", po::value<std::string>());
  po::positional_options_description positional;
  positional.add("input", 1);
  try {
    po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(e.what());
  }
  if (vm.count("help")) {
    std::cout << visible << "\n" << help_text;
    return false;
  }
  if (!vm.count("input")) throw UsageError("missing the input " + what);
  if (!vm.count("out")) throw UsageError("missing --out OUT.rawlog");
  input = vm["input"].as<std::string>();
  output = vm["out"].as<std::string>();
  return true;
}

bool stderrIsTerminal() {
  return isatty(fileno(stderr)) != 0;
}

void Progress::update(double fraction, std::size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (shown_ && now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  shown_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  if (fraction >= 0 && fraction <= 1) {
    const double left = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "\r%5.1f%%  %7zu scans  %8.0f scans/s  %6.0f s left   ", 100 * fraction,
                 done, rate, left);
  } else {
    std::fprintf(stderr, "\r%7zu scans  %8.0f scans/s   ", done, rate);
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

void addBagOptions(po::options_description& o, const std::string& prefix) {
  const BagOptions d;
  const auto text = [&](const char* what) { return prefix + what; };
  o.add_options()("scan-topic", po::value<std::string>(),
                  text("the sensor_msgs/LaserScan topic (default: the bag's only one)").c_str())(
      "odom-topic", po::value<std::string>(),
      text("odometry from this nav_msgs/Odometry topic instead of /tf").c_str())(
      "odom-frame", po::value<std::string>()->default_value(d.odom_frame),
      text("the odometry frame of /tf (odometry: odom-frame -> base-frame)").c_str())(
      "base-frame", po::value<std::string>()->default_value(d.base_frame),
      text("the robot's frame (the laser's mount: base-frame -> the scan's frame)").c_str())(
      "gt-frame", po::value<std::string>()->default_value(d.gt_frame),
      text("ground truth is this frame's transform to base-frame in /tf").c_str());
}

BagOptions bagOptions(const po::variables_map& vm) {
  BagOptions bag;
  if (vm.count("scan-topic")) bag.scan_topic = vm["scan-topic"].as<std::string>();
  if (vm.count("odom-topic")) bag.odom_topic = vm["odom-topic"].as<std::string>();
  bag.odom_frame = vm["odom-frame"].as<std::string>();
  bag.base_frame = vm["base-frame"].as<std::string>();
  bag.gt_frame = vm["gt-frame"].as<std::string>();
  return bag;
}

void addCarmenOptions(po::options_description& o, const std::string& prefix) {
  const auto text = [&](const char* what) { return prefix + what; };
  o.add_options()("skip-bad-lines", text("skip malformed lines of known types (counted in the "
                                         "summary) instead of stopping at the first one")
                                        .c_str())(
      "fov", po::value<double>(),
      text("field of view of every laser line [deg], overriding the PARAM lines and ROBOTLASER1 "
           "fields; the angular step then follows from the beam count")
          .c_str())(
      "carmen-odometry", po::value<std::string>(),
      text("the odometry stream: laser (each laser line's odometry fields; ROBOTLASER1: the "
           "latest ODOM line) or odom (the ODOM lines); map: overrides [input] carmen_odometry, "
           "import-carmen: laser unless given")
          .c_str());
}

std::optional<CarmenOdometrySource> carmenOptions(const po::variables_map& vm,
                                                  CarmenOptions& carmen) {
  carmen.skip_bad_lines = vm.count("skip-bad-lines") > 0;
  if (vm.count("fov")) {
    carmen.fov_deg = vm["fov"].as<double>();
    if (!(carmen.fov_deg > 0 && carmen.fov_deg <= 360))
      throw UsageError("--fov: must be in (0, 360] degrees");
  }
  if (!vm.count("carmen-odometry")) return std::nullopt;
  try {
    return parseCarmenOdometry(vm["carmen-odometry"].as<std::string>());
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--carmen-odometry: ") + e.what());
  }
}

}  // namespace dynamap::app
