// dynamap: maps environments in which things move. main() only dispatches to a subcommand and
// turns exceptions into one-line errors with a documented exit status.

#include <malloc.h>

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

// A demo build (make demo, -DDYNAMAP_DEMO=ON) has map and config only: its other commands keep
// their line without a body, so that asking for one says how to get it.
#ifdef DYNAMAP_MAP_ONLY
#define DYNAMAP_FULL_BUILD(run) nullptr
#else
#define DYNAMAP_FULL_BUILD(run) run
#endif

// One line per subcommand.
const Command kCommands[] = {
    {"map", "build the static map, the dynamic map and the object table from a log",
     dynamap::app::runMap},
    {"simulate", "run a scenario file: a rawlog with exact ground truth",
     DYNAMAP_FULL_BUILD(dynamap::app::runSimulate)},
    {"import-carmen", "convert a CARMEN log (.log[.gz]) to an MRPT rawlog with its timestamps",
     DYNAMAP_FULL_BUILD(dynamap::app::runImportCarmen)},
    {"import-bag", "convert a ROS bag (ROS 1 .bag, ROS 2 .mcap/.db3) to an MRPT rawlog",
     DYNAMAP_FULL_BUILD(dynamap::app::runImportBag)},
    {"export-bag", "write a log as a ROS 2 bag (.mcap or .db3: LaserScan, /tf, /tf_static)",
     DYNAMAP_FULL_BUILD(dynamap::app::runExportBag)},
    {"eval", "score a map result against a scenario's ground truth (paper's Table 3, SA/DA)",
     DYNAMAP_FULL_BUILD(dynamap::app::runEval)},
    {"config", "print the built-in configuration (an .ini to start from) or its table of keys",
     dynamap::app::runConfig},
    {"perturb", "a log with known poses as a rawlog whose odometry drifts, and its truth",
     DYNAMAP_FULL_BUILD(dynamap::app::runPerturb)},
    {"train-legs", "grow the people detector's leg classifier from ROS bags of marked legs",
     DYNAMAP_FULL_BUILD(dynamap::app::runTrainLegs)},
};

void printHelp(std::ostream& out) {
  out << "dynamap — maps of environments in which things move\n\n"
         "usage: dynamap <command> [options]     (dynamap <command> --help for its options)\n\n"
         "commands:\n";
  for (const auto& c : kCommands)
    if (c.run != nullptr)
      out << "  " << c.name << std::string(16 - std::string(c.name).size(), ' ') << c.summary << "\n";
  out << "\nexit status: 0 success, 1 error, 2 bad command line, 3 bad configuration,\n"
         "             4 input ended in a fault (outputs cover the part before it)\n";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynamap::app;
  // A run allocates and frees grid-sized buffers (a layer regrown, an image, a mask) many times.
  // glibc would hand each one above its mmap threshold back to the kernel and fault every page in
  // again on the next: keep freed memory in the heap instead. The peak is bounded as before by
  // [dynamic_map] max_map_size_m; only its return to the system waits for the process's end.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
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
    if (c.run == nullptr) {
      std::cerr << "dynamap: '" << name << "' is not in this build, which has map and config only "
                << "(make demo); make build builds every command into build/\n";
      return kExitUsage;
    }
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
  std::cerr << "dynamap: unknown command '" << name << "' (see dynamap --help)\n";
  return kExitUsage;
}
