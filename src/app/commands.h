#pragma once
// The dynamap subcommands. Each lives in src/app/<name>_command.cpp and receives the arguments
// after its name. Errors are exceptions, caught once in main().

#include <stdexcept>
#include <string>
#include <vector>

namespace dynamap {
struct MapConfig;
}

namespace dynamap::app {

/// Exit statuses, documented in the README.
constexpr int kExitOk = 0;
constexpr int kExitError = 1;         ///< an error while running (I/O, bad input data)
constexpr int kExitUsage = 2;         ///< bad command line
constexpr int kExitConfig = 3;        ///< bad configuration or scenario file
constexpr int kExitPartialInput = 4;  ///< input ended in a fault; outputs cover the good part

using Args = std::vector<std::string>;

int runMap(const Args& args);
int runSimulate(const Args& args);
int runImportCarmen(const Args& args);
int runImportBag(const Args& args);
int runExportBag(const Args& args);
int runEval(const Args& args);
int runConfig(const Args& args);
int runPerturb(const Args& args);
int runTrainLegs(const Args& args);
/// perturb --add-objects (perturb_objects.cpp): cylinders added to the scans of `input`, the
/// edited log and its truth written into `dir` as `name`.* (name empty: the input's stem).
int runAddObjects(const std::string& input, const std::string& dir, const std::string& spec,
                  std::string name, const MapConfig& config);

/// Thrown for a bad command line; main() prints it with a pointer to --help.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dynamap::app
