// dynamap config: the configuration every run starts from, as a file to edit or as the table of
// every key.

#include <iostream>

#include "cli.h"
#include "dynamap/pipeline/mapper.h"

namespace dynamap::app {

int runConfig(const Args& args) {
  po::options_description opts("options");
  opts.add_options()("help,h", "explain the options")(
      "markdown", "print the table of every key (section, key, default, range, meaning)");
  po::variables_map vm;
  if (!parseArgs(args, opts, {}, vm,
                 "usage: dynamap config [--markdown]\n\n"
                 "Prints the built-in configuration (what a run without --config uses) as an .ini\n"
                 "file to start your own from: dynamap config > my.ini"))
    return kExitOk;
  if (vm.count("markdown")) {
    std::cout << optionsMarkdown(MapConfig::describe());
  } else {
    const MapConfig defaults;  // named: GCC 12 warns of a temporary's strings as uninitialized
    defaults.writeIni(std::cout);
  }
  return kExitOk;
}

}  // namespace dynamap::app
