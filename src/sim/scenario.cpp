#include "dynamap/sim/scenario.h"

#include <mrpt/img/CImage.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "scenario_parse.h"

namespace dynamap::sim {

namespace parse {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
std::string fmt(Vec2 p) {
  return "(" + fmt(p.x) + " " + fmt(p.y) + ")";
}

std::vector<std::pair<int, std::string>> numberedKeys(const IniFile& ini,
                                                      const std::string& section,
                                                      const std::string& prefix,
                                                      const std::vector<std::string>& others) {
  std::vector<std::pair<int, std::string>> out;
  for (const auto& k : ini.keys(section)) {
    if (std::find(others.begin(), others.end(), k) != others.end()) continue;
    long n = 0;
    const std::string head = prefix + ".";
    if (k.rfind(head, 0) != 0) ini.fail(section, k, "unknown key (expected " + head + "<n>)");
    const std::string num = k.substr(head.size());
    if (!parseLong(num, n) || n < 1 || std::to_string(n) != num) {
      ini.fail(section, k, "unknown key (expected " + head + "<n> with n a positive integer)");
    }
    out.emplace_back(static_cast<int>(n), k);
  }
  std::sort(out.begin(), out.end());
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (out[i].first == out[i - 1].first) ini.fail(section, out[i].second, "duplicate number");
  }
  return out;
}

std::vector<double> numbers(const IniFile& ini, const std::string& s, const std::string& k,
                            std::size_t count, const std::string& form) {
  const auto v = ini.getDoubles(s, k);
  if (v.size() != count) {
    ini.fail(s, k,
             "expected " + std::to_string(count) + " numbers \"" + form + "\", got " +
                 std::to_string(v.size()));
  }
  return v;
}

std::vector<Vec2> points(const std::vector<double>& v, std::size_t first) {
  std::vector<Vec2> out;
  for (std::size_t i = first; i + 1 < v.size(); i += 2) out.push_back({v[i], v[i + 1]});
  return out;
}

double positive(const IniFile& ini, const std::string& s, const std::string& k, double v) {
  if (!(v > 0)) ini.fail(s, k, fmt(v) + " must be > 0");
  return v;
}
double nonNegative(const IniFile& ini, const std::string& s, const std::string& k, double v) {
  if (!(v >= 0)) ini.fail(s, k, fmt(v) + " must be >= 0");
  return v;
}
int integer(const IniFile& ini, const std::string& s, const std::string& k, double v) {
  if (v != std::floor(v) || std::abs(v) > 1e9) ini.fail(s, k, fmt(v) + " must be an integer");
  return static_cast<int>(v);
}

namespace {
std::string wallName(const std::string& key) {
  return key.rfind("[", 0) == 0 ? key : "[world] " + key;
}
}  // namespace

std::string wallOverlapping(const Scenario& sc, Vec2 c, double r) {
  for (std::size_t i = 0; i < sc.world.segments.size(); ++i) {
    if (discOverlapsSegment(c, r, sc.world.segments[i])) return wallName(sc.wall_keys[i]);
  }
  if (discOverlapsGrid(c, r, sc.world.grid)) return "[world] map_image";
  return "";
}

std::string wallCrossed(const Scenario& sc, const Segment& leg) {
  for (std::size_t i = 0; i < sc.world.segments.size(); ++i) {
    if (segmentsIntersect(leg, sc.world.segments[i])) return wallName(sc.wall_keys[i]);
  }
  if (segmentCrossesGrid(leg, sc.world.grid)) return "[world] map_image";
  return "";
}

std::vector<std::string> keysWithPrefix(const IniFile& ini, const std::string& section,
                                        const std::vector<std::string>& prefixes) {
  std::vector<std::string> out;
  for (const auto& k : ini.keys(section)) {
    for (const auto& p : prefixes) {
      if (k.rfind(p + ".", 0) == 0) out.push_back(k);
    }
  }
  return out;
}

void checkRoute(const IniFile& ini, const Scenario& sc, const std::string& section) {
  const auto& w = sc.robot.waypoints;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const std::string wall = wallOverlapping(sc, w[i], kWallClearance);
    if (!wall.empty()) {
      ini.fail(section, "waypoints",
               "waypoint " + std::to_string(i + 1) + " " + fmt(w[i]) + " is inside " + wall);
    }
  }
  const std::size_t legs = w.size() < 2 ? 0 : (sc.robot.loop ? w.size() : w.size() - 1);
  for (std::size_t i = 0; i < legs; ++i) {
    const Segment leg{w[i], w[(i + 1) % w.size()]};
    const std::string wall = wallCrossed(sc, leg);
    if (!wall.empty()) {
      ini.fail(section, "waypoints",
               "the leg " + fmt(leg.a) + " -> " + fmt(leg.b) + " crosses " + wall);
    }
  }
}

std::size_t objectIndex(const Scenario& sc, int id) {
  for (std::size_t i = 0; i < sc.objects.size(); ++i) {
    if (sc.objects[i].id == id) return i;
  }
  return sc.objects.size();
}

namespace {
bool gliding(const Scenario& sc, int object_id, double t) {
  return std::any_of(sc.moves.begin(), sc.moves.end(), [&](const MoveSpec& m) {
    return m.object_id == object_id && t > m.t_start && t < m.tEnd();
  });
}
}  // namespace

void checkObjectsApart(const IniFile& ini, const Scenario& sc, double t, int mover,
                       const std::string& section, const std::string& key) {
  const std::size_t i = objectIndex(sc, mover);
  const Vec2 p = objectPositionAt(sc, i, t);
  for (std::size_t j = 0; j < sc.objects.size(); ++j) {
    if (j == i || gliding(sc, sc.objects[j].id, t)) continue;
    const Vec2 q = objectPositionAt(sc, j, t);
    if (distance(p, q) < (sc.objects[i].diameter + sc.objects[j].diameter) / 2) {
      ini.fail(section, key,
               "overlaps object." + std::to_string(sc.objects[j].id) + " at " + fmt(q) +
                   " (t = " + fmt(t) + " s)");
    }
  }
}

}  // namespace parse

namespace {

using namespace parse;

const std::vector<std::string> kSections = {"scenario", "world",   "robot", "laser",
                                            "odometry", "objects", "moves", "people"};

// ---- sections -----------------------------------------------------------------------------

// Bounds of what a scenario may ask for (a file is not trusted to be reasonable).
constexpr double kMaxDurationS = 86400;
constexpr double kMaxScans = 1e6;
constexpr double kMaxBeamSamples = 1e9;
constexpr std::uintmax_t kMaxImageBytes = std::uintmax_t{64} << 20;
constexpr std::size_t kMaxImageSide = 16384;

void readScenarioSection(const IniFile& ini, Scenario& sc) {
  const std::string s = "scenario";
  ini.requireKnownKeys(s, {"name", "duration_s", "seed"});
  sc.name = ini.requireString(s, "name");
  const bool safe = !sc.name.empty() && std::all_of(sc.name.begin(), sc.name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!safe) ini.fail(s, "name", "'" + sc.name + "' must be letters, digits, '_' or '-'");
  if (!ini.hasKey(s, "duration_s")) ini.fail(s, "duration_s", "missing (required)");
  sc.duration_s = positive(ini, s, "duration_s", ini.getDouble(s, "duration_s", 0));
  if (sc.duration_s > kMaxDurationS)
    ini.fail(s, "duration_s", fmt(sc.duration_s) + " must be <= 86400 (a day)");
  const long seed = ini.getInt(s, "seed", 1);
  if (seed < 0) ini.fail(s, "seed", "must be >= 0");
  sc.seed = static_cast<std::uint64_t>(seed);
}

WallGrid loadWallImage(const IniFile& ini, const std::string& path) {
  const std::string s = "world";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) ||
      std::filesystem::file_size(path, ec) > kMaxImageBytes) {
    // /dev/zero, a fifo or a directory would reach OpenCV: refused by name first.
    ini.fail(s, "map_image", "'" + path + "' is not an image file of at most 64 MiB");
  }
  mrpt::img::CImage img;
  bool loaded = false;
  try {
    loaded = img.loadFromFile(path, 0);
  } catch (const std::exception&) {  // OpenCV's own exceptions for a corrupt file
  }
  if (!loaded) ini.fail(s, "map_image", "cannot read image '" + path + "'");
  if (img.getWidth() > kMaxImageSide || img.getHeight() > kMaxImageSide) {
    ini.fail(s, "map_image", "'" + path + "' is larger than 16384 pixels on a side");
  }
  if (img.isColor()) img = img.grayscale();
  WallGrid g;
  g.width = static_cast<int>(img.getWidth());
  g.height = static_cast<int>(img.getHeight());
  g.wall.resize(static_cast<std::size_t>(g.width) * g.height);
  for (int row = 0; row < g.height; ++row) {
    const int iy = g.height - 1 - row;  // image rows run downwards, world y upwards
    for (int ix = 0; ix < g.width; ++ix) g.wall[iy * g.width + ix] = img.at<uint8_t>(ix, row) < 128;
  }
  return g;
}

void readWorldSection(const IniFile& ini, const std::string& base_dir, Scenario& sc) {
  const std::string s = "world";
  const std::vector<std::string> image_keys = {"map_image", "map_resolution", "map_origin"};
  for (const auto& [n, key] : numberedKeys(ini, s, "wall", image_keys)) {
    const auto v = numbers(ini, s, key, 4, "x1 y1 x2 y2");
    const Segment seg{{v[0], v[1]}, {v[2], v[3]}};
    if (distance(seg.a, seg.b) == 0) ini.fail(s, key, "wall has zero length");
    sc.world.segments.push_back(seg);
    sc.wall_keys.push_back(key);
  }
  if (ini.hasKey(s, "map_image")) {
    const std::string rel = ini.requireString(s, "map_image");
    sc.map_image = (std::filesystem::path(base_dir) / rel).lexically_normal().string();
    if (!ini.hasKey(s, "map_resolution")) ini.fail(s, "map_resolution", "missing (map_image set)");
    if (!ini.hasKey(s, "map_origin")) ini.fail(s, "map_origin", "missing (map_image set)");
    WallGrid g = loadWallImage(ini, sc.map_image);
    g.resolution = positive(ini, s, "map_resolution", ini.getDouble(s, "map_resolution", 0));
    const auto o = numbers(ini, s, "map_origin", 2, "x y");
    g.origin = {o[0], o[1]};
    sc.world.grid = std::move(g);
  } else {
    for (const auto& k : {"map_resolution", "map_origin"}) {
      if (ini.hasKey(s, k)) ini.fail(s, k, "given without map_image");
    }
  }
  if (sc.world.segments.empty() && sc.world.grid.width == 0) {
    ini.fail(s, "", "no walls: give wall.<n> keys or a map_image");
  }
}

void readRobotSection(const IniFile& ini, Scenario& sc) {
  const std::string s = "robot";
  ini.requireKnownKeys(s, {"waypoints", "loop", "speed_mps", "turn_rate_dps", "scan_rate_hz"});
  if (!ini.hasKey(s, "waypoints")) ini.fail(s, "waypoints", "missing (required)");
  const auto v = ini.getDoubles(s, "waypoints");
  if (v.empty() || v.size() % 2 != 0) ini.fail(s, "waypoints", "expected x y pairs");
  RobotSpec& r = sc.robot;
  r.waypoints = points(v, 0);
  r.loop = ini.getBool(s, "loop", r.loop);
  r.speed_mps = positive(ini, s, "speed_mps", ini.getDouble(s, "speed_mps", r.speed_mps));
  r.turn_rate_dps =
      positive(ini, s, "turn_rate_dps", ini.getDouble(s, "turn_rate_dps", r.turn_rate_dps));
  r.scan_rate_hz =
      positive(ini, s, "scan_rate_hz", ini.getDouble(s, "scan_rate_hz", r.scan_rate_hz));
  if (r.scan_rate_hz > 1000) ini.fail(s, "scan_rate_hz", fmt(r.scan_rate_hz) + " must be <= 1000");
  const std::size_t n = r.waypoints.size();
  for (std::size_t i = 0; n > 1 && i < (r.loop ? n : n - 1); ++i) {
    if (distance(r.waypoints[i], r.waypoints[(i + 1) % n]) == 0) {
      ini.fail(s, "waypoints",
               "waypoints " + std::to_string(i + 1) + " and " + std::to_string((i + 1) % n + 1) +
                   " coincide (the robot could not face the next one)");
    }
  }
}

void readLaserSection(const IniFile& ini, Scenario& sc) {
  const std::string s = "laser";
  ini.requireKnownKeys(s, {"beams", "fov_deg", "max_range_m", "range_noise_std_m", "mount"});
  LaserSpec& l = sc.laser;
  l.beams = static_cast<int>(ini.getInt(s, "beams", l.beams));
  if (l.beams < 2 || l.beams > 100000) ini.fail(s, "beams", "must be in [2, 100000]");
  l.fov_deg = positive(ini, s, "fov_deg", ini.getDouble(s, "fov_deg", l.fov_deg));
  if (l.fov_deg > 360) ini.fail(s, "fov_deg", fmt(l.fov_deg) + " must be <= 360");
  l.max_range_m = positive(ini, s, "max_range_m", ini.getDouble(s, "max_range_m", l.max_range_m));
  l.range_noise_std_m = nonNegative(ini, s, "range_noise_std_m",
                                    ini.getDouble(s, "range_noise_std_m", l.range_noise_std_m));
  if (ini.hasKey(s, "mount")) {
    const auto m = numbers(ini, s, "mount", 3, "x y yaw");
    l.mount = {m[0], m[1]};
    l.mount_yaw_deg = m[2];
  }
}

void readOdometrySection(const IniFile& ini, Scenario& sc) {
  const std::string s = "odometry";
  ini.requireKnownKeys(s, {"noise_xy_per_m", "noise_yaw_per_rad"});
  OdometrySpec& o = sc.odometry;
  o.noise_xy_per_m =
      nonNegative(ini, s, "noise_xy_per_m", ini.getDouble(s, "noise_xy_per_m", o.noise_xy_per_m));
  o.noise_yaw_per_rad = nonNegative(ini, s, "noise_yaw_per_rad",
                                    ini.getDouble(s, "noise_yaw_per_rad", o.noise_yaw_per_rad));
}

void readObjectsSection(const IniFile& ini, Scenario& sc) {
  const std::string s = "objects";
  for (const auto& [n, key] : numberedKeys(ini, s, "object")) {
    const auto v = numbers(ini, s, key, 3, "diameter x y");
    ObjectSpec o{n, positive(ini, s, key, v[0]), {v[1], v[2]}};
    sc.objects.push_back(o);
  }
}

void readMovesSection(const IniFile& ini, Scenario& sc) {
  const std::string s = "moves";
  for (const auto& [n, key] : numberedKeys(ini, s, "move")) {
    const auto v = numbers(ini, s, key, 5, "t_start object_id x y duration");
    MoveSpec m{n, integer(ini, s, key, v[1]), v[0], {v[2], v[3]}, v[4]};
    if (m.t_start < 0 || m.t_start > sc.duration_s) {
      ini.fail(s, key, "t_start " + fmt(m.t_start) + " is outside [0, duration_s]");
    }
    if (m.duration < 0) ini.fail(s, key, "duration " + fmt(m.duration) + " must be >= 0");
    const bool known = std::any_of(sc.objects.begin(), sc.objects.end(),
                                   [&](const ObjectSpec& o) { return o.id == m.object_id; });
    if (!known) ini.fail(s, key, "no [objects] object." + std::to_string(m.object_id));
    sc.moves.push_back(m);
  }
  std::stable_sort(sc.moves.begin(), sc.moves.end(),
                   [](const MoveSpec& a, const MoveSpec& b) { return a.t_start < b.t_start; });
}

PersonSpec* personById(Scenario& sc, int id) {
  for (auto& p : sc.people) {
    if (p.id == id) return &p;
  }
  return nullptr;
}

// legs.<n> = leg_diameter stride: person n is two legs.
void readLegs(const IniFile& ini, Scenario& sc) {
  const std::string s = "people";
  for (const auto& [n, key] :
       numberedKeys(ini, s, "legs", keysWithPrefix(ini, s, {"person", "pause"}))) {
    const auto v = numbers(ini, s, key, 2, "leg_diameter stride");
    PersonSpec* p = personById(sc, n);
    if (!p) ini.fail(s, key, "no person." + std::to_string(n));
    p->leg_diameter = positive(ini, s, key, v[0]);
    if (!(v[1] >= 0)) ini.fail(s, key, "stride must be >= 0");
    p->stride = v[1];
    if (2 * p->leg_diameter > p->diameter) {
      ini.fail(s, key, "two legs of this diameter do not fit in the person's diameter");
    }
  }
}

// pause.<n> = person_id point seconds: the walker stands at that path point (1-based).
void readPauses(const IniFile& ini, Scenario& sc) {
  const std::string s = "people";
  for (const auto& [n, key] :
       numberedKeys(ini, s, "pause", keysWithPrefix(ini, s, {"person", "legs"}))) {
    (void)n;
    const auto v = numbers(ini, s, key, 3, "person_id point seconds");
    PersonSpec* p = v[0] == std::floor(v[0]) ? personById(sc, static_cast<int>(v[0])) : nullptr;
    if (!p) ini.fail(s, key, "no person with this id");
    if (!(v[1] >= 1 && v[1] <= static_cast<double>(p->path.size()) && v[1] == std::floor(v[1]))) {
      ini.fail(s, key, "point must be 1 .. " + std::to_string(p->path.size()) + " (a path point)");
    }
    const std::size_t point = static_cast<std::size_t>(v[1]) - 1;
    for (const auto& other : p->pauses) {
      if (other.point == point) ini.fail(s, key, "a second pause at the same point");
    }
    p->pauses.push_back({point, positive(ini, s, key, v[2])});
  }
  for (auto& p : sc.people) {
    std::sort(p.pauses.begin(), p.pauses.end(),
              [](const PauseSpec& a, const PauseSpec& b) { return a.point < b.point; });
  }
}

void readPeopleSection(const IniFile& ini, Scenario& sc) {
  const std::string s = "people";
  for (const auto& [n, key] :
       numberedKeys(ini, s, "person", keysWithPrefix(ini, s, {"legs", "pause"}))) {
    const auto v = ini.getDoubles(s, key);
    if (v.size() < 6 || v.size() % 2 != 0) {
      ini.fail(s, key, "expected \"diameter speed_mps x0 y0 x1 y1 ...\" (two points at least)");
    }
    PersonSpec p;
    p.id = n;
    p.diameter = positive(ini, s, key, v[0]);
    p.speed_mps = positive(ini, s, key, v[1]);
    p.path = points(v, 2);
    double length = 0;
    for (std::size_t i = 1; i < p.path.size(); ++i) length += distance(p.path[i - 1], p.path[i]);
    if (length == 0) ini.fail(s, key, "the path has zero length");
    sc.people.push_back(p);
  }
  readLegs(ini, sc);
  readPauses(ini, sc);
}

// ---- checks across sections ---------------------------------------------------------------

void checkPeople(const IniFile& ini, const Scenario& sc) {
  for (const auto& p : sc.people) {
    for (std::size_t i = 1; i < p.path.size(); ++i) {
      const std::string wall = wallCrossed(sc, {p.path[i - 1], p.path[i]});
      if (!wall.empty()) {
        ini.fail("people", "person." + std::to_string(p.id),
                 "the path " + fmt(p.path[i - 1]) + " -> " + fmt(p.path[i]) + " crosses " + wall);
      }
    }
  }
}

void checkObjects(const IniFile& ini, const Scenario& sc) {
  for (const auto& o : sc.objects) {
    const std::string key = "object." + std::to_string(o.id);
    const std::string wall = wallOverlapping(sc, o.start, o.diameter / 2);
    if (!wall.empty()) ini.fail("objects", key, "overlaps " + wall + " at its start");
    checkObjectsApart(ini, sc, 0, o.id, "objects", key);
  }
  std::map<int, double> busy_until;  // object id -> end of its last move
  for (const auto& m : sc.moves) {
    const std::string key = "move." + std::to_string(m.id);
    const ObjectSpec& o = sc.objects[objectIndex(sc, m.object_id)];
    auto it = busy_until.find(m.object_id);
    if (it != busy_until.end() && m.t_start < it->second) {
      ini.fail("moves", key,
               "starts before object." + std::to_string(o.id) +
                   "'s previous move ends (t = " + fmt(it->second) + " s)");
    }
    busy_until[m.object_id] = m.tEnd();
    const std::string wall = wallOverlapping(sc, m.to, o.diameter / 2);
    if (!wall.empty()) ini.fail("moves", key, "the target " + fmt(m.to) + " overlaps " + wall);
    checkObjectsApart(ini, sc, m.tEnd(), m.object_id, "moves", key);
  }
}

}  // namespace

// The run a file asks for is bounded before it starts: at most a million scans and a thousand
// million beams (a rawlog of some 5 GB), all sessions together.
void parse::checkRunSize(const IniFile& ini, const Scenario& sc, double total_s,
                         const std::string& section) {
  const double scans = total_s * sc.robot.scan_rate_hz;
  if (scans > kMaxScans || scans * sc.laser.beams > kMaxBeamSamples) {
    ini.fail(section, "duration_s",
             fmt(scans) + " scans of " + std::to_string(sc.laser.beams) +
                 " beams (duration_s x scan_rate_hz x beams) exceed 1e6 scans or 1e9 beams");
  }
}

namespace {

void checkSections(const IniFile& ini) {
  std::vector<std::string> known = kSections;
  for (const auto& section : ini.sections()) {
    if (section.rfind("session.", 0) == 0) known.push_back(section);  // numbers: readSessions
  }
  ini.requireKnownSections(known);
  for (const auto& s : {"scenario", "world", "robot", "laser"}) {
    if (!ini.hasSection(s)) ini.fail(s, "", "missing section (required)");
  }
}

}  // namespace

Scenario parseScenario(const IniFile& ini, const std::string& base_dir) {
  checkSections(ini);
  Scenario sc;
  sc.file = ini.name();
  readScenarioSection(ini, sc);
  readWorldSection(ini, base_dir, sc);
  readRobotSection(ini, sc);
  readLaserSection(ini, sc);
  readOdometrySection(ini, sc);
  readObjectsSection(ini, sc);
  readMovesSection(ini, sc);
  readPeopleSection(ini, sc);
  checkRoute(ini, sc, "robot");
  checkObjects(ini, sc);
  checkPeople(ini, sc);
  checkRunSize(ini, sc, sc.duration_s, "scenario");
  readSessions(ini, sc);
  return sc;
}

Scenario loadScenario(const std::string& path) {
  const IniFile ini = IniFile::fromFile(path);
  return parseScenario(ini, std::filesystem::path(path).parent_path().string());
}

Vec2 objectPositionAt(const Scenario& sc, std::size_t index, double t) {
  const ObjectSpec& o = sc.objects.at(index);
  Vec2 p = o.start;
  for (const auto& m : sc.moves) {  // sorted by t_start, and an object's moves never overlap
    if (m.object_id != o.id || t < m.t_start) continue;
    if (m.duration == 0 || t >= m.tEnd()) {
      p = m.to;
      continue;
    }
    const double u = (t - m.t_start) / m.duration;
    return {p.x + u * (m.to.x - p.x), p.y + u * (m.to.y - p.y)};
  }
  return p;
}

Vec2 moveOrigin(const Scenario& sc, const MoveSpec& m) {
  Vec2 p = sc.objects.at(objectIndex(sc, m.object_id)).start;
  for (const auto& other : sc.moves) {  // sorted by t_start
    if (other.id == m.id) break;
    if (other.object_id == m.object_id) p = other.to;
  }
  return p;
}

}  // namespace dynamap::sim
