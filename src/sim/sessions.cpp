// Multi-session scenarios: the [session.N] sections, each session as a scenario of its own, and
// the truth of what changed between sessions (docs/scenario_format.md, "Sessions").

#include <algorithm>
#include <set>

#include "dynamap/sim/scenario.h"
#include "scenario_parse.h"

namespace dynamap::sim {
namespace {

using namespace parse;

// Sessions are a day apart on the clock: what a later session sees is later than anything the
// earlier one saw, as in a building logged every night.
constexpr double kSessionSpacingS = 86400;
constexpr int kMaxSessions = 100;

/// The number a wall key ends in: "wall.7" and "[session.3] wall.7" are wall 7.
int wallNumber(const std::string& key) {
  return std::stoi(key.substr(key.rfind('.') + 1));
}

std::string sectionOf(int n) {
  return "session." + std::to_string(n);
}

/// The world and objects as `prev` leaves them, with session `spec`'s changes made.
Scenario applySession(const Scenario& base, const Scenario& prev, const SessionSpec& spec) {
  Scenario next = prev;
  next.name = base.name + ".s" + std::to_string(spec.number);
  next.duration_s = spec.duration_s;
  next.seed = base.seed + static_cast<std::uint64_t>(spec.number - 1);
  next.clock_offset_s = kSessionSpacingS * (spec.number - 1);
  next.robot.waypoints = spec.waypoints;
  next.robot.loop = spec.loop;
  for (std::size_t i = 0; i < prev.objects.size(); ++i) {
    next.objects[i].start = objectPositionAt(prev, i, prev.duration_s);
  }
  next.moves.clear();
  next.sessions.clear();
  for (const auto& m : spec.moved) next.objects[objectIndex(next, m.object_id)].start = m.to;
  for (int id : spec.removed) next.objects.erase(next.objects.begin() + objectIndex(next, id));
  next.objects.insert(next.objects.end(), spec.added.begin(), spec.added.end());
  std::sort(next.objects.begin(), next.objects.end(),
            [](const ObjectSpec& a, const ObjectSpec& b) { return a.id < b.id; });
  for (int n : spec.walls_removed) {
    for (std::size_t i = 0; i < next.wall_keys.size(); ++i) {
      if (wallNumber(next.wall_keys[i]) != n) continue;
      next.wall_keys.erase(next.wall_keys.begin() + i);
      next.world.segments.erase(next.world.segments.begin() + i);
      break;
    }
  }
  for (std::size_t i = 0; i < spec.walls_added.size(); ++i) {
    next.world.segments.push_back(spec.walls_added[i]);
    next.wall_keys.push_back("[" + sectionOf(spec.number) + "] wall." +
                             std::to_string(spec.wall_numbers_added[i]));
  }
  return next;
}

/// Every object and wall number the scenario has used so far: a new object or wall takes a
/// number never used before, so the truth names each thing once.
struct UsedNumbers {
  std::set<int> objects, walls;
};

std::vector<std::string> keysOtherThan(const IniFile& ini, const std::string& s,
                                       const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& k : ini.keys(s)) {
    if (k.rfind(prefix + ".", 0) != 0) out.push_back(k);
  }
  return out;
}

/// The object numbers of a list key ("remove = 3 7"), each standing in `prev`, each once.
std::vector<int> numberList(const IniFile& ini, const std::string& s, const std::string& key,
                            const std::set<int>& standing, const std::string& what) {
  std::vector<int> out;
  for (double v : ini.getDoubles(s, key)) {
    const int n = integer(ini, s, key, v);
    if (!standing.count(n)) {
      ini.fail(s, key, "no " + what + " " + std::to_string(n) + " stands in the session before");
    }
    if (std::count(out.begin(), out.end(), n))
      ini.fail(s, key, what + " " + std::to_string(n) + " twice");
    out.push_back(n);
  }
  return out;
}

void readSessionObjects(const IniFile& ini, const std::string& s, const Scenario& prev,
                        UsedNumbers& used, SessionSpec& spec) {
  std::set<int> standing;
  for (const auto& o : prev.objects) standing.insert(o.id);
  for (const auto& [n, key] : numberedKeys(ini, s, "move", keysOtherThan(ini, s, "move"))) {
    const auto v = numbers(ini, s, key, 2, "x y");
    if (!standing.count(n)) {
      ini.fail(s, key, "no object " + std::to_string(n) + " stands in the session before");
    }
    spec.moved.push_back({n, {v[0], v[1]}});
  }
  spec.removed = numberList(ini, s, "remove", standing, "object");
  std::sort(spec.removed.begin(), spec.removed.end());
  for (int id : spec.removed) {
    if (ini.hasKey(s, "move." + std::to_string(id))) {
      ini.fail(s, "remove",
               "object " + std::to_string(id) + " is also moved (move." + std::to_string(id) + ")");
    }
  }
  for (const auto& [n, key] : numberedKeys(ini, s, "object", keysOtherThan(ini, s, "object"))) {
    const auto v = numbers(ini, s, key, 3, "diameter x y");
    if (!used.objects.insert(n).second) {
      ini.fail(s, key,
               "object " + std::to_string(n) + " existed before (a new one takes a new number)");
    }
    spec.added.push_back({n, positive(ini, s, key, v[0]), {v[1], v[2]}});
  }
}

void readSessionWalls(const IniFile& ini, const std::string& s, const Scenario& prev,
                      UsedNumbers& used, SessionSpec& spec) {
  std::set<int> standing;
  for (const auto& k : prev.wall_keys) standing.insert(wallNumber(k));
  spec.walls_removed = numberList(ini, s, "remove_walls", standing, "wall");
  std::sort(spec.walls_removed.begin(), spec.walls_removed.end());
  for (const auto& [n, key] : numberedKeys(ini, s, "wall", keysOtherThan(ini, s, "wall"))) {
    const auto v = numbers(ini, s, key, 4, "x1 y1 x2 y2");
    const Segment seg{{v[0], v[1]}, {v[2], v[3]}};
    if (distance(seg.a, seg.b) == 0) ini.fail(s, key, "wall has zero length");
    if (!used.walls.insert(n).second) {
      ini.fail(s, key,
               "wall " + std::to_string(n) + " existed before (a new one takes a new number)");
    }
    spec.walls_added.push_back(seg);
    spec.wall_numbers_added.push_back(n);
  }
}

SessionSpec readSession(const IniFile& ini, int n, const Scenario& base, const Scenario& prev,
                        UsedNumbers& used) {
  const std::string s = sectionOf(n);
  for (const auto& k : ini.keys(s)) {
    const bool numbered =
        k.rfind("move.", 0) == 0 || k.rfind("object.", 0) == 0 || k.rfind("wall.", 0) == 0;
    const std::vector<std::string> plain = {"duration_s", "waypoints", "loop", "remove",
                                            "remove_walls"};
    if (!numbered && std::find(plain.begin(), plain.end(), k) == plain.end()) {
      ini.fail(s, k, "unknown key");
    }
  }
  SessionSpec spec;
  spec.number = n;
  spec.duration_s = positive(ini, s, "duration_s", ini.getDouble(s, "duration_s", base.duration_s));
  if (!ini.hasKey(s, "waypoints"))
    ini.fail(s, "waypoints", "missing (each session drives its own route)");
  const auto v = ini.getDoubles(s, "waypoints");
  if (v.empty() || v.size() % 2 != 0) ini.fail(s, "waypoints", "expected x y pairs");
  spec.waypoints = points(v, 0);
  spec.loop = ini.getBool(s, "loop", base.robot.loop);
  readSessionObjects(ini, s, prev, used, spec);
  readSessionWalls(ini, s, prev, used, spec);
  return spec;
}

/// Session `spec`'s world as built: the route clear of the walls, every object clear of the
/// walls and of each other.
void checkSession(const IniFile& ini, const Scenario& next, const SessionSpec& spec) {
  const std::string s = sectionOf(spec.number);
  checkRoute(ini, next, s);
  for (const auto& o : next.objects) {
    std::string key = "object." + std::to_string(o.id);
    if (!ini.hasKey(s, key)) key = "move." + std::to_string(o.id);
    if (!ini.hasKey(s, key)) key = "";  // an object left standing where a new wall is
    const std::string wall = wallOverlapping(next, o.start, o.diameter / 2);
    if (!wall.empty()) {
      ini.fail(s, key,
               "object " + std::to_string(o.id) + " at " + fmt(o.start) + " overlaps " + wall);
    }
    checkObjectsApart(ini, next, 0, o.id, s, key);
  }
}

}  // namespace

void parse::readSessions(const IniFile& ini, Scenario& sc) {
  std::vector<std::pair<int, std::string>> found;
  for (const auto& s : ini.sections()) {
    if (s.rfind("session.", 0) != 0) continue;
    long n = 0;
    const std::string num = s.substr(8);
    if (!parseLong(num, n) || n < 2 || n > kMaxSessions || std::to_string(n) != num) {
      ini.fail(s, "", "expected [session.N] with N = 2 .. 100 (session 1 is the scenario itself)");
    }
    found.emplace_back(static_cast<int>(n), s);
  }
  std::sort(found.begin(), found.end());
  UsedNumbers used;
  for (const auto& o : sc.objects) used.objects.insert(o.id);
  for (const auto& k : sc.wall_keys) used.walls.insert(wallNumber(k));
  Scenario prev = sc;
  double total_s = sc.duration_s;
  for (std::size_t i = 0; i < found.size(); ++i) {
    const int n = static_cast<int>(i) + 2;
    if (found[i].first != n)
      ini.fail(sectionOf(n), "", "missing: sessions are numbered 2, 3, ... without gaps");
    const SessionSpec spec = readSession(ini, n, sc, prev, used);
    Scenario next = applySession(sc, prev, spec);
    checkSession(ini, next, spec);
    total_s += spec.duration_s;
    checkRunSize(ini, sc, total_s, sectionOf(n));
    sc.sessions.push_back(spec);
    prev = std::move(next);
  }
}

Scenario sessionScenario(const Scenario& scenario, int n) {
  if (n < 1 || n > static_cast<int>(scenario.sessions.size()) + 1) {
    throw std::out_of_range("sessionScenario: no session " + std::to_string(n));
  }
  Scenario s = scenario;
  s.sessions.clear();
  for (int k = 2; k <= n; ++k) s = applySession(scenario, s, scenario.sessions[k - 2]);
  return s;
}

void forEachSession(const Scenario& scenario, const std::function<void(const Scenario&)>& f) {
  Scenario s = scenario;
  s.sessions.clear();
  f(s);
  for (const SessionSpec& spec : scenario.sessions) {
    s = applySession(scenario, s, spec);
    f(s);
  }
}

namespace {

void objectChanges(const Scenario& prev, const SessionSpec& spec, std::vector<SessionChange>& out) {
  auto place = [&](int id) {
    return objectPositionAt(prev, objectIndex(prev, id), prev.duration_s);
  };
  auto size = [&](int id) { return prev.objects[objectIndex(prev, id)].diameter; };
  std::vector<SessionChange> rows;
  for (const auto& m : spec.moved) {
    rows.push_back(
        {spec.number, "object_moved", m.object_id, size(m.object_id), place(m.object_id), m.to});
  }
  for (const auto& o : spec.added)
    rows.push_back({spec.number, "object_new", o.id, o.diameter, {}, o.start});
  for (int id : spec.removed)
    rows.push_back({spec.number, "object_gone", id, size(id), place(id), {}});
  out.insert(out.end(), rows.begin(), rows.end());
}

void wallChanges(const Scenario& prev, const SessionSpec& spec, std::vector<SessionChange>& out) {
  for (std::size_t i = 0; i < spec.walls_added.size(); ++i) {
    const Segment& w = spec.walls_added[i];
    out.push_back(
        {spec.number, "structure_added", spec.wall_numbers_added[i], distance(w.a, w.b), w.a, w.b});
  }
  for (int n : spec.walls_removed) {
    for (std::size_t i = 0; i < prev.wall_keys.size(); ++i) {
      if (wallNumber(prev.wall_keys[i]) != n) continue;
      const Segment& w = prev.world.segments[i];
      out.push_back({spec.number, "structure_removed", n, distance(w.a, w.b), w.a, w.b});
    }
  }
}

}  // namespace

std::vector<SessionChange> sessionChanges(const Scenario& scenario) {
  std::vector<SessionChange> out;
  Scenario prev = sessionScenario(scenario, 1);
  for (const auto& spec : scenario.sessions) {
    objectChanges(prev, spec, out);
    wallChanges(prev, spec, out);
    prev = applySession(scenario, prev, spec);
  }
  return out;
}

}  // namespace dynamap::sim
