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

}  // namespace dynamap::app
