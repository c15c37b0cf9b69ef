#pragma once
// Options of the dual grid (section [dynamic_map]) and of scan insertion (section [insertion]).
// Defaults are the paper's where it gives values (thresholds) and chosen here otherwise; every
// field is validated when loaded, and every error names the file, the section and the key.

#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <iosfwd>
#include <string>

namespace mrpt::obs {
class CObservation2DRangeScan;
}

namespace dynamap {

struct RangeData;
class IniFile;
template <typename T>
class OptionTable;

/// The inverse sensor model and thresholds of Wolf & Sukhatme's two maps. Probabilities are
/// P(occupied); "high" values are > 0.5, "low" values < 0.5.
struct DynamicMapOptions : public mrpt::config::CLoadableOptions {
  static constexpr const char* kSection = "dynamic_map";

  double resolution = 0.05;  ///< [m] cell size of S and D; > 0
  /// [m] the grid never grows wider or taller than this: a scan that would make it (a pose
  /// jump, a corrupt pose) is skipped and counted; in [1, 10000]. 600 m at 5 cm: 0.9 GB.
  double max_map_size_m = 600;
  double free_threshold = 0.1;     ///< S cell is Free when P(occ) < this; in (0, 1)
  double object_threshold = 0.85;  ///< D cell is part of an object when P(occ) > this; in (0, 1)
  // Static map S: the update applied for each (previous S state, observation) pair.
  double s_hit_notfree = 0.7;  ///< beam ends in a cell S did not know as free: high
  double s_hit_free = 0.45;    ///< beam ends in a cell S knew as free (something moved in): low
  double s_miss = 0.4;         ///< beam crosses the cell: low
  // Dynamic map D. 0.59 makes 5 clean hits (1 s at 5 Hz) cross object_threshold 0.85.
  double d_hit_free = 0.59;    ///< beam ends in a cell S knew as free: high
  double d_hit_notfree = 0.4;  ///< beam ends in a cell S did not know as free: low
  double d_miss = 0.4;         ///< beam crosses the cell: low
  /// D never grows past this P(occ), so an object that leaves decays below object_threshold in
  /// a few scans instead of the dozens a saturated cell would need; in (object_threshold, 1).
  double d_max = 0.95;
  /// A hit counts as "in free space" only if no cell within this many cells is occupied in S
  /// (P(occ) > 0.5): range noise and grazing beams at walls then never look like objects.
  /// 0 is the paper's rule; in [0, 3].
  int wall_guard_cells = 1;
  /// [m] Width of the band along a surface that a beam hitting it at a slant does not free.
  /// The surface runs through the neighbouring beams' end points; a beam at incidence a
  /// crosses the band over surface_guard / sin(a) of its length, one at right angles over
  /// surface_guard, and stops freeing the difference earlier (at right angles: as MRPT, every
  /// cell up to the hit). A beam grazing a wall then no longer frees the wall's own cells,
  /// which range noise and the cell grid spread over a band about a cell wide. In [0, 1].
  double surface_guard = 0.05;
  /// [m] The guard along a beam never exceeds this (a beam nearly parallel to a wall, or at
  /// the edge of an object in front of a wall); in [0, 10].
  double surface_guard_max = 1.0;
  /// D never falls below this P(occ). Without a floor, a cell crossed by beams for minutes
  /// would need as many hits to show an object that then arrives; 0.5 (the prior) makes 5 hits
  /// enough wherever the object appears; in (0, object_threshold).
  double d_min = 0.5;
  /// While more than this share of the last scans' hits (a moving average over about five)
  /// lands where S holds free space, some on surfaces wider than any object, the scans
  /// disagree with the map: the poses are off (a drifting log, a loop that did not close), and
  /// a hit in free space is a wall seen from the wrong place, not something that moved in. D
  /// then holds still (S is updated as always; Mapper decides, DynamicGridMap::holdDynamic).
  /// With right poses the share stays lower (people and moved objects are a few beams). 1 =
  /// never; in (0, 1].
  double d_hold_share = 0.8;

  /// Every key of [dynamic_map]: name, member, range, unit, meaning (see OptionTable).
  static const OptionTable<DynamicMapOptions>& table();
  /// Strict load: unknown keys, malformed numbers and out-of-range values throw ConfigError.
  void load(const IniFile& ini);
  /// Throws ConfigError ("<source>: [dynamic_map] key: why") for the first rule broken: the
  /// table's ranges, then the model's own rules (updates that move an 8-bit cell; thresholds in
  /// order).
  void validate(const std::string& source) const;
  /// Writes the section, one key per line with its meaning, in ini syntax (reloadable).
  void writeIni(std::ostream& out) const;

  // mrpt::config::CLoadableOptions
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                          const std::string& section) override;
  void dumpToTextStream(std::ostream& out) const override;
};

/// The MRPT insertion options that apply to dynamap's ray pass (section [insertion]).
struct InsertionOptions {
  static constexpr const char* kSection = "insertion";

  double max_distance_insertion = 15.0;  ///< [m] rays are cut at this range; > 0
  /// A no-echo beam frees space up to half the last valid range (as MRPT does).
  bool invalid_ranges_as_free = true;
  double horizontal_tolerance_deg = 0.05;  ///< [deg] max pitch/roll of a scan to insert it; >= 0

  /// The geometry of `scan` as insertion reads it (makeRangeData() at this range and tolerance),
  /// into `out`, reusing its buffers: the mapper, the grid and slam all work a scan out so.
  void rangeData(const mrpt::obs::CObservation2DRangeScan& scan, RangeData& out) const;

  static const OptionTable<InsertionOptions>& table();
  void load(const IniFile& ini);
  void validate(const std::string& source) const;
  void writeIni(std::ostream& out) const;
};

}  // namespace dynamap
