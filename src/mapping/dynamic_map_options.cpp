#include "dynamap/mapping/dynamic_map_options.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/base/option_table.h"
#include "dynamap/base/range_data.h"

namespace dynamap {
namespace {

// MRPT's 8-bit cells hold 16 log-odds units per nat: an update must move a cell by >= 1 unit.
bool movesCell(double p) {
  return std::abs(16.0 * std::log(p / (1.0 - p))) >= 0.5;
}

// A model value within its range must still change an 8-bit cell.
void requireMovesCell(const std::string& src, const char* key, double p) {
  if (movesCell(p)) return;
  std::ostringstream m;
  m << p << " is too close to 0.5 to change an 8-bit cell (use "
    << (p > 0.5 ? ">= 0.508" : "<= 0.492") << ")";
  rejectValue(src, DynamicMapOptions::kSection, key, m.str());
}

using O = DynamicMapOptions;
const Range kProbability = Range::open(0, 1);
const Range kHigh = Range::open(0.5, 1);  // a "high" model value: > 0.5
const Range kLow = Range::open(0, 0.5);   // a "low" one

}  // namespace

const OptionTable<DynamicMapOptions>& DynamicMapOptions::table() {
  static const OptionTable<O> t(
      kSection,
      {
          {"resolution", &O::resolution, Range::closed(0.005, 10), "m", "cell size of S and D, > 0",
           8},
          {"max_map_size_m", &O::max_map_size_m, Range::closed(1, 10000), "m",
           "the grid's largest width or height", 4},
          {"free_threshold", &O::free_threshold, kProbability, "",
           "S cell is Free below this P(occ)", 4},
          {"object_threshold", &O::object_threshold, kProbability, "",
           "D cell is an object above this P(occ)", 1},
          {"s_hit_notfree", &O::s_hit_notfree, kHigh, "", "S update, hit after NotFree (> 0.5)", 5},
          {"s_hit_free", &O::s_hit_free, kLow, "", "S update, hit after Free (< 0.5)", 7},
          {"s_miss", &O::s_miss, kLow, "", "S update, beam crossed (< 0.5)", 12},
          {"d_hit_free", &O::d_hit_free, kHigh, "", "D update, hit after Free (> 0.5)", 7},
          {"d_hit_notfree", &O::d_hit_notfree, kLow, "", "D update, hit after NotFree (< 0.5)", 5},
          {"d_miss", &O::d_miss, kLow, "", "D update, beam crossed (< 0.5)", 12},
          {"d_max", &O::d_max, kProbability, "", "D saturates at this P(occ)", 12},
          {"d_min", &O::d_min, kProbability, "", "D never falls below this P(occ)", 13},
          {"wall_guard_cells", &O::wall_guard_cells, Range::closed(0, 3), "",
           "hits within this many cells of S-occupied ones are not in free space", 4},
          {"surface_guard", &O::surface_guard, Range::closed(0, 1), "m",
           "beams do not free cells this close (across) to the surface they hit", 5},
          {"surface_guard_max", &O::surface_guard_max, Range::closed(0, 10), "m",
           "...nor farther than this back along the beam", 1},
          {"d_hold_share", &O::d_hold_share, Range::openClosed(0, 1), "",
           "D holds still while more of the last scans' hits land in S's free space (poses off); 1 = never", 6},
      });
  return t;
}

void DynamicMapOptions::load(const IniFile& ini) {
  table().load(ini, *this);
  validate(ini.name());
}

void DynamicMapOptions::validate(const std::string& src) const {
  table().checkRanges(*this, src);
  const char* sec = kSection;
  for (const auto& [key, p] : {std::pair<const char*, double>{"s_hit_notfree", s_hit_notfree},
                               {"s_hit_free", s_hit_free},
                               {"s_miss", s_miss},
                               {"d_hit_free", d_hit_free},
                               {"d_hit_notfree", d_hit_notfree},
                               {"d_miss", d_miss}}) {
    requireMovesCell(src, key, p);
  }
  if (!(free_threshold < object_threshold)) {
    rejectValue(src, sec, "free_threshold", "must be below object_threshold");
  }
  if (!(d_max > object_threshold)) {
    rejectValue(src, sec, "d_max", "must be above object_threshold, or no object is ever seen");
  }
  if (!(d_min < object_threshold)) {
    rejectValue(src, sec, "d_min", "must be below object_threshold, or every cell is an object");
  }
}

void DynamicMapOptions::writeIni(std::ostream& out) const {
  table().write(*this, out);
}

void DynamicMapOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                           const std::string& section) {
  load(IniFile::fromMrptSection(source, section, kSection));  // the same checks as an ini file
}

void DynamicMapOptions::dumpToTextStream(std::ostream& out) const {
  writeIni(out);
}

const OptionTable<InsertionOptions>& InsertionOptions::table() {
  using I = InsertionOptions;
  static const OptionTable<I> t(
      kSection, {
                    {"max_distance_insertion", &I::max_distance_insertion,
                     Range::openClosed(0, 1000), "m", "rays cut here"},
                    {"invalid_ranges_as_free",
                     &I::invalid_ranges_as_free,
                     {},
                     "",
                     "no-echo beams free space up to half the last valid range"},
                    {"horizontal_tolerance_deg", &I::horizontal_tolerance_deg, Range::closed(0, 90),
                     "deg", "max pitch/roll of an inserted scan"},
                });
  return t;
}

void InsertionOptions::load(const IniFile& ini) {
  table().load(ini, *this);
}

void InsertionOptions::validate(const std::string& src) const {
  table().checkRanges(*this, src);
}

void InsertionOptions::writeIni(std::ostream& out) const {
  table().write(*this, out);
}

void InsertionOptions::rangeData(const mrpt::obs::CObservation2DRangeScan& scan,
                                 RangeData& out) const {
  makeRangeData(scan, max_distance_insertion, horizontal_tolerance_deg * M_PI / 180.0, out);
}

}  // namespace dynamap
