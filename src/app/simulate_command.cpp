// dynamap simulate: runs a scenario file and writes a rawlog with its ground truth.

#include <boost/program_options.hpp>

#include <iostream>

#include "commands.h"
#include "dynamap/sim/simulator.h"

namespace dynamap::app {
namespace {

namespace po = boost::program_options;

po::options_description simulateOptions() {
  po::options_description o(
      "usage: dynamap simulate --scenario <file.ini> --out <dir>\n\n"
      "Simulates a robot with a 2D laser driving through a scenario (walls, movable objects,\n"
      "walking people; format in docs/scenario_format.md) and writes into <dir>, each file named\n"
      "after the scenario's [scenario] name:\n"
      "  <name>.rawlog       gz MRPT rawlog (observations only): ODOMETRY, LASER, GT per scan\n"
      "  <name>.gt.txt       'timestamp x y phi', the true pose of every scan\n"
      "  <name>.objects.csv  every object and person at every scan, with the beams it got\n"
      "  <name>.moves.csv    every object move\n"
      "  <name>.world.png    the world at t = 0\n"
      "A scenario with [session.N] sections writes session 1 as above, each later session as\n"
      "<name>.s<N>.* (its own route, the changes made before it applied, a day later on the\n"
      "clock) and the truth of the changes between sessions as <name>.changes.csv.\n"
      "The same scenario gives byte-identical files on every run.\n\noptions");
  o.add_options()("help,h", "print this help")(
      "scenario", po::value<std::string>()->value_name("FILE"), "scenario .ini file (required)")(
      "out", po::value<std::string>()->value_name("DIR"),
      "output directory, created if missing (required)");
  return o;
}

}  // namespace

int runSimulate(const Args& args) {
  const auto options = simulateOptions();
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(args).options(options).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(e.what());
  }
  if (vm.count("help")) {
    std::cout << options << "\n";
    return kExitOk;
  }
  if (!vm.count("scenario")) throw UsageError("--scenario is required");
  if (!vm.count("out")) throw UsageError("--out is required");
  const std::string out = vm["out"].as<std::string>();
  const sim::Scenario scenario = sim::loadScenario(vm["scenario"].as<std::string>());
  const std::vector<std::size_t> scans = sim::writeSessions(scenario, out);
  const auto files = sim::outputPaths(scenario, out);
  std::cout << "dynamap simulate: " << scenario.name << ": " << scans.front() << " scans, "
            << scenario.objects.size() << " objects, " << scenario.moves.size() << " moves, "
            << scenario.people.size() << " people -> " << files.rawlog << " (+ .gt.txt, "
            << ".objects.csv, .moves.csv, .world.png)\n";
  for (std::size_t i = 1; i < scans.size(); ++i) {
    std::cout << "  session " << i + 1 << ": " << scans[i] << " scans -> " << out << "/"
              << scenario.name << ".s" << i + 1 << ".rawlog\n";
  }
  if (scans.size() > 1) {
    std::cout << "  " << sim::sessionChanges(scenario).size() << " changes between sessions -> "
              << out << "/" << scenario.name << ".changes.csv\n";
  }
  return kExitOk;
}

}  // namespace dynamap::app
