#pragma once
// Internal to the scenario reader (scenario.cpp) and its sessions (sessions.cpp): the checked
// getters every section uses, and the wall checks. Each failure is ini.fail(section, key, ...),
// a ConfigError naming the file, the section and the key.

#include <string>
#include <utility>
#include <vector>

#include "dynamap/base/ini.h"
#include "dynamap/sim/scenario.h"

namespace dynamap::sim::parse {

// A waypoint closer than this to a wall counts as inside it: walls have no thickness in the
// simulation, and a robot standing on one would see through it.
constexpr double kWallClearance = 0.05;

std::string fmt(double v);
std::string fmt(Vec2 p);

/// Keys "<prefix>.<n>" of a section, sorted by n; any other key not in `others` is an error.
std::vector<std::pair<int, std::string>> numberedKeys(const IniFile& ini,
                                                      const std::string& section,
                                                      const std::string& prefix,
                                                      const std::vector<std::string>& others = {});
/// Exactly `count` numbers, else an error quoting `form`.
std::vector<double> numbers(const IniFile& ini, const std::string& s, const std::string& k,
                            std::size_t count, const std::string& form);
/// v[first], v[first+1], ... as x y pairs.
std::vector<Vec2> points(const std::vector<double>& v, std::size_t first);
double positive(const IniFile& ini, const std::string& s, const std::string& k, double v);
double nonNegative(const IniFile& ini, const std::string& s, const std::string& k, double v);
int integer(const IniFile& ini, const std::string& s, const std::string& k, double v);

/// The wall a disc overlaps, as "[world] wall.<n>" (a session's own wall: "[session.N]
/// wall.<n>") or "[world] map_image", or "" if none.
std::string wallOverlapping(const Scenario& sc, Vec2 c, double r);
/// The wall the segment crosses, named the same way, or "".
std::string wallCrossed(const Scenario& sc, const Segment& leg);

/// The keys of `section` that start with one of `prefixes` (numberedKeys' "others" for the rest).
std::vector<std::string> keysWithPrefix(const IniFile& ini, const std::string& section,
                                        const std::vector<std::string>& prefixes);
/// Every waypoint clear of the walls, no leg through one; errors on `section` waypoints.
void checkRoute(const IniFile& ini, const Scenario& sc, const std::string& section);
/// Index into sc.objects of object `id`, or sc.objects.size().
std::size_t objectIndex(const Scenario& sc, int id);
/// Every object at rest at time t must be clear of object `mover` at rest. `section` and `key`
/// are what the configuration at time t was made by (an object at t = 0, a move at its arrival).
void checkObjectsApart(const IniFile& ini, const Scenario& sc, double t, int mover,
                       const std::string& section, const std::string& key);

/// At most a million scans and a thousand million beams in `total_s` seconds of the run.
void checkRunSize(const IniFile& ini, const Scenario& sc, double total_s,
                  const std::string& section);
/// Reads the [session.N] sections of a scenario whose other sections are read and checked.
void readSessions(const IniFile& ini, Scenario& sc);

}  // namespace dynamap::sim::parse
