#include "dynamap/mapping/dynamic_map_options.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "dynamap/base/ini.h"

namespace dynamap {
namespace {

const char* const kMapKeys[] = {
    "resolution", "max_map_size_m", "free_threshold",   "object_threshold", "s_hit_notfree",
    "s_hit_free", "s_miss",         "d_hit_free",       "d_hit_notfree",    "d_miss",
    "d_max",      "d_min",          "wall_guard_cells", "surface_guard",    "surface_guard_max"};

[[noreturn]] void reject(const std::string& source, const char* section, const char* key,
                         const std::string& why) {
  rejectValue(source, section, key, why);
}

// MRPT's 8-bit cells hold 16 log-odds units per nat: an update must move a cell by >= 1 unit.
bool movesCell(double p) {
  return std::abs(16.0 * std::log(p / (1.0 - p))) >= 0.5;
}

// p must lie in (lo, hi), a "high" or "low" model value, and move an 8-bit cell.
void requireModelValue(const std::string& src, const char* key, double p, bool high) {
  const double lo = high ? 0.5 : 0.0, hi = high ? 1.0 : 0.5;
  std::ostringstream m;
  if (!(p > lo && p < hi)) {
    m << p << " must be a " << (high ? "high" : "low") << " probability, in (" << lo << ", " << hi
      << ")";
  } else if (!movesCell(p)) {
    m << p << " is too close to 0.5 to change an 8-bit cell (use "
      << (high ? ">= 0.508" : "<= 0.492") << ")";
  } else {
    return;
  }
  reject(src, DynamicMapOptions::kSection, key, m.str());
}

void requireHigh(const std::string& src, const char* key, double p) {
  requireModelValue(src, key, p, true);
}
void requireLow(const std::string& src, const char* key, double p) {
  requireModelValue(src, key, p, false);
}

void requireOpenUnit(const std::string& src, const char* key, double p) {
  if (!(p > 0.0 && p < 1.0)) {
    std::ostringstream m;
    m << p << " must be in (0, 1)";
    reject(src, DynamicMapOptions::kSection, key, m.str());
  }
}

}  // namespace

void DynamicMapOptions::load(const IniFile& ini) {
  const std::string s = kSection;
  ini.requireKnownKeys(s, {std::begin(kMapKeys), std::end(kMapKeys)});
  resolution = ini.getDouble(s, "resolution", resolution);
  max_map_size_m = ini.getDouble(s, "max_map_size_m", max_map_size_m);
  free_threshold = ini.getDouble(s, "free_threshold", free_threshold);
  object_threshold = ini.getDouble(s, "object_threshold", object_threshold);
  s_hit_notfree = ini.getDouble(s, "s_hit_notfree", s_hit_notfree);
  s_hit_free = ini.getDouble(s, "s_hit_free", s_hit_free);
  s_miss = ini.getDouble(s, "s_miss", s_miss);
  d_hit_free = ini.getDouble(s, "d_hit_free", d_hit_free);
  d_hit_notfree = ini.getDouble(s, "d_hit_notfree", d_hit_notfree);
  d_miss = ini.getDouble(s, "d_miss", d_miss);
  d_max = ini.getDouble(s, "d_max", d_max);
  d_min = ini.getDouble(s, "d_min", d_min);
  wall_guard_cells = static_cast<int>(ini.getInt(s, "wall_guard_cells", wall_guard_cells));
  surface_guard = ini.getDouble(s, "surface_guard", surface_guard);
  surface_guard_max = ini.getDouble(s, "surface_guard_max", surface_guard_max);
  validate(ini.name());
}

void DynamicMapOptions::validate(const std::string& src) const {
  const char* sec = kSection;
  if (!(resolution > 0.0)) reject(src, sec, "resolution", "must be > 0 m");
  if (resolution < 0.005 || resolution > 10.0) {
    reject(src, sec, "resolution", "must be within [0.005, 10] m");
  }
  requireInRange(src, sec, "max_map_size_m", max_map_size_m, 1.0, 10000.0, "within [1, 10000] m");
  requireOpenUnit(src, "free_threshold", free_threshold);
  requireOpenUnit(src, "object_threshold", object_threshold);
  if (!(free_threshold < object_threshold)) {
    reject(src, sec, "free_threshold", "must be below object_threshold");
  }
  requireHigh(src, "s_hit_notfree", s_hit_notfree);
  requireLow(src, "s_hit_free", s_hit_free);
  requireLow(src, "s_miss", s_miss);
  requireHigh(src, "d_hit_free", d_hit_free);
  requireLow(src, "d_hit_notfree", d_hit_notfree);
  requireLow(src, "d_miss", d_miss);
  requireOpenUnit(src, "d_max", d_max);
  if (!(d_max > object_threshold)) {
    reject(src, sec, "d_max", "must be above object_threshold, or no object is ever seen");
  }
  requireInRange(src, sec, "wall_guard_cells", wall_guard_cells, 0, 3, "an integer in [0, 3]");
  requireInRange(src, sec, "surface_guard", surface_guard, 0.0, 1.0, "within [0, 1] m");
  requireInRange(src, sec, "surface_guard_max", surface_guard_max, 0.0, 10.0, "within [0, 10] m");
  requireOpenUnit(src, "d_min", d_min);
  if (!(d_min < object_threshold)) {
    reject(src, sec, "d_min", "must be below object_threshold, or every cell is an object");
  }
}

void DynamicMapOptions::writeIni(std::ostream& out) const {
  out << std::setprecision(10);
  out << "[" << kSection << "]\n"
      << "resolution = " << resolution << "        ; [m] cell size of S and D, > 0\n"
      << "max_map_size_m = " << max_map_size_m << "    ; [m] the grid's largest width or height\n"
      << "free_threshold = " << free_threshold << "    ; S cell is Free below this P(occ)\n"
      << "object_threshold = " << object_threshold << " ; D cell is an object above this P(occ)\n"
      << "s_hit_notfree = " << s_hit_notfree << "     ; S update, hit after NotFree (> 0.5)\n"
      << "s_hit_free = " << s_hit_free << "       ; S update, hit after Free (< 0.5)\n"
      << "s_miss = " << s_miss << "            ; S update, beam crossed (< 0.5)\n"
      << "d_hit_free = " << d_hit_free << "       ; D update, hit after Free (> 0.5)\n"
      << "d_hit_notfree = " << d_hit_notfree << "     ; D update, hit after NotFree (< 0.5)\n"
      << "d_miss = " << d_miss << "            ; D update, beam crossed (< 0.5)\n"
      << "d_max = " << d_max << "            ; D saturates at this P(occ)\n"
      << "d_min = " << d_min << "             ; D never falls below this P(occ)\n"
      << "wall_guard_cells = " << wall_guard_cells
      << "    ; hits within this many cells of S-occupied ones are not in free space\n"
      << "surface_guard = " << surface_guard
      << "     ; [m] beams do not free cells this close (across) to the surface they hit\n"
      << "surface_guard_max = " << surface_guard_max
      << " ; [m] ...nor farther than this back along the beam\n";
}

void DynamicMapOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                           const std::string& section) {
  load(IniFile::fromMrptSection(source, section, kSection));  // the same checks as an ini file
}

void DynamicMapOptions::dumpToTextStream(std::ostream& out) const {
  writeIni(out);
}

void InsertionOptions::load(const IniFile& ini) {
  const std::string s = kSection;
  ini.requireKnownKeys(
      s, {"max_distance_insertion", "invalid_ranges_as_free", "horizontal_tolerance_deg"});
  max_distance_insertion = ini.getDouble(s, "max_distance_insertion", max_distance_insertion);
  invalid_ranges_as_free = ini.getBool(s, "invalid_ranges_as_free", invalid_ranges_as_free);
  horizontal_tolerance_deg = ini.getDouble(s, "horizontal_tolerance_deg", horizontal_tolerance_deg);
  validate(ini.name());
}

void InsertionOptions::validate(const std::string& src) const {
  if (!(max_distance_insertion > 0.0 && max_distance_insertion <= 1000.0)) {
    reject(src, kSection, "max_distance_insertion", "must be in (0, 1000] m");
  }
  if (!(horizontal_tolerance_deg >= 0.0 && horizontal_tolerance_deg <= 90.0)) {
    reject(src, kSection, "horizontal_tolerance_deg", "must be in [0, 90] degrees");
  }
}

void InsertionOptions::writeIni(std::ostream& out) const {
  out << std::setprecision(10);
  out << "[" << kSection << "]\n"
      << "max_distance_insertion = " << max_distance_insertion << " ; [m] rays cut here\n"
      << "invalid_ranges_as_free = " << (invalid_ranges_as_free ? "true" : "false")
      << " ; no-echo beams free space up to half the last valid range\n"
      << "horizontal_tolerance_deg = " << horizontal_tolerance_deg
      << " ; [deg] max pitch/roll of an inserted scan\n";
}

}  // namespace dynamap
