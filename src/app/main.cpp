// dynamap: maps environments in which things move. main() only dispatches to a subcommand and
// turns exceptions into one-line errors with a documented exit status.

#include <iostream>

#include "commands.h"
#include "dynamap/base/ini.h"
#include "dynamap/base/printable.h"

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const dynamap::app::Args&);
};

// One line per subcommand.
const Command kCommands[] = {
    {"map", "build the static map, the dynamic map and the object table from a log",
     dynamap::app::runMap},
    {"config", "print the built-in configuration (an .ini to start from) or its table of keys",
     dynamap::app::runConfig},
#ifndef DYNAMAP_MAP_ONLY
    {"simulate", "run a scenario file: a rawlog with exact ground truth",
     dynamap::app::runSimulate},
    {"import-carmen", "convert a CARMEN log (.log[.gz]) to an MRPT rawlog with its timestamps",
     dynamap::app::runImportCarmen},
    {"import-bag", "convert a ROS bag (ROS 1 .bag, ROS 2 .mcap/.db3) to an MRPT rawlog",
     dynamap::app::runImportBag},
    {"export-bag", "write a log as a ROS 2 bag (.mcap or .db3: LaserScan, /tf, /tf_static)",
     dynamap::app::runExportBag},
    {"eval", "score a map result against a scenario's ground truth (paper's Table 3, SA/DA)",
     dynamap::app::runEval},
    {"perturb", "a log with known poses as a rawlog whose odometry drifts, and its truth",
     dynamap::app::runPerturb},
    {"train-legs", "grow the people detector's leg classifier from ROS bags of marked legs",
     dynamap::app::runTrainLegs},
#endif
};

#ifdef DYNAMAP_MAP_ONLY
// The commands a demo build (make demo, -DDYNAMAP_DEMO=ON) leaves out.
const char* const kFullBuildOnly[] = {"simulate", "import-carmen", "import-bag", "export-bag",
                                      "eval", "perturb", "train-legs"};
#endif

void printHelp(std::ostream& out) {
  out << "dynamap — maps of environments in which things move\n\n"
         "usage: dynamap <command> [options]     (dynamap <command> --help for its options)\n\n"
         "commands:\n";
  for (const auto& c : kCommands)
    out << "  " << c.name << std::string(16 - std::string(c.name).size(), ' ') << c.summary << "\n";
  out << "\nexit status: 0 success, 1 error, 2 bad command line, 3 bad configuration,\n"
         "             4 input ended in a fault (outputs cover the part before it)\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynamap::app;
  if (argc < 2) {
    printHelp(std::cerr);
    return kExitUsage;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    printHelp(std::cout);
    return kExitOk;
  }
  const Args args(argv + 2, argv + argc);
  for (const auto& c : kCommands) {
    if (name != c.name) continue;
    try {
      return c.run(args);
    } catch (const UsageError& e) {
      std::cerr << "dynamap " << name << ": " << dynamap::printable(e.what()) << " (see dynamap " << name
                << " --help)\n";
      return kExitUsage;
    } catch (const dynamap::ConfigError& e) {
      std::cerr << "dynamap " << name << ": " << dynamap::printable(e.what()) << "\n";
      return kExitConfig;
    } catch (const std::exception& e) {
      std::cerr << "dynamap " << name << ": " << dynamap::printable(e.what()) << "\n";
      return kExitError;
    }
  }
#ifdef DYNAMAP_MAP_ONLY
  for (const char* c : kFullBuildOnly) {
    if (name != c) continue;
    std::cerr << "dynamap: '" << name << "' is not in this build, which has map and config only "
              << "(make demo); make build builds every command into build/\n";
    return kExitUsage;
  }
#endif
  std::cerr << "dynamap: unknown command '" << name << "' (see dynamap --help)\n";
  return kExitUsage;
}
