#pragma once
// Small helpers shared by the subcommands: option parsing with boost::program_options and the
// progress line.

#include <boost/program_options.hpp>

#include <chrono>
#include <optional>
#include <string>

#include "commands.h"
#include "dynamap/input/bag_source.h"
#include "dynamap/input/carmen_reader.h"

namespace dynamap::app {

namespace po = boost::program_options;

/// Parses `args` against `options` (with `positional` names, may be empty). Returns false after
/// printing help when --help was given. Throws UsageError for a bad command line.
bool parseArgs(const Args& args, const po::options_description& options,
               const po::positional_options_description& positional, po::variables_map& vm,
               const std::string& usage);

/// A progress line on stderr, redrawn at most a few times a second, only when stderr is a
/// terminal (or when forced by --verbose).
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled) {}
  /// `fraction` in [0, 1] or negative when unknown; `done` scans so far.
  void update(double fraction, std::size_t done);
  void finish();

 private:
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_{};
};

/// An import command's line: the `visible` options, one input file as a positional argument and
/// --out. Prints `visible` and `help_text` and returns false for --help; otherwise fills `input`
/// and `output` or throws UsageError naming what is missing ("missing the input <what>").
bool parseImportCommand(const Args& args, const po::options_description& visible,
                        const std::string& help_text, const std::string& what,
                        po::variables_map& vm, std::string& input, std::string& output);

bool stderrIsTerminal();
/// Declares the ROS bag options (--scan-topic, --odom-topic, --odom-frame, --base-frame,
/// --gt-frame) with the defaults of BagOptions, each meaning led by `prefix`.
void addBagOptions(po::options_description& options, const std::string& prefix);
/// The ROS bag options (--scan-topic, --odom-topic, --odom-frame, --base-frame, --gt-frame) of a
/// parsed command line that declares them, as map and import-bag do.
BagOptions bagOptions(const po::variables_map& vm);
/// Declares the CARMEN options (--skip-bad-lines, --fov, --carmen-odometry), each meaning led
/// by `prefix`, as map and import-carmen do.
void addCarmenOptions(po::options_description& options, const std::string& prefix);
/// --skip-bad-lines and --fov (UsageError unless in (0, 360]) of a parsed command line into
/// `carmen`; the --carmen-odometry stream when given (UsageError unless laser or odom).
std::optional<CarmenOdometrySource> carmenOptions(const po::variables_map& vm,
                                                  CarmenOptions& carmen);

}  // namespace dynamap::app
