#pragma once
// ObjectOptions: the object tracker's section [objects] of the configuration.

#include <iosfwd>
#include <string>

namespace dynamap {

class IniFile;
template <typename T>
class OptionTable;

/// Options of the object tracker (section [objects]). Lengths in metres, counts in scans/cells.
struct ObjectOptions {
  static constexpr const char* kSection = "objects";

  bool enabled = true;  ///< track objects at all (false: no object outputs)
  double join_distance =
      0.15;  ///< [m] object cells this close (centre to centre) form one cluster; [0.01, 2]
  int min_cells = 2;       ///< fewer cells than this is not an object; [1, 1000]
  /// A cluster short of min_cells also counts the D cells beside it above this P(occ), in S's
  /// free space and off the walls: a far object's arc, whose hits spread over its cells from
  /// scan to scan, brings one cell to object_threshold and its neighbours part of the way.
  /// 0.8 is four more hits than misses. 0 = off; [0, 1).
  double support_threshold = 0.8;
  double min_size = 0.06;  ///< [m] smaller estimated sizes are noise; [0, max_size)
  double max_size = 1.2;  ///< [m] larger clusters are not objects (walls seen off by localisation);
                          ///< (min_size, 20]
  /// a new cluster is reported, with a provisional identity, once this many scans of its run
  /// of filter passes have shown its whole outline (see outline_jump) and the identity the
  /// outlines' size gives holds for any size within report_errors of their errors; else it
  /// waits for confirm_scans; [1, confirm_scans]
  int report_scans = 2;
  /// ...errors: 1 on 15 simulated worlds reports as rightly as 2 did and sooner (corridors'
  /// median 2.0 -> 1.3 s); 0.5 named wrong objects on two of them; [0, 10]
  double report_errors = 1;
  /// [m] a scan shows a cluster's whole outline when the beams on it form a run whose ranges
  /// step by at most this, both beams beside the run end farther than this behind it, and the
  /// run, fitted as one object, is no larger than max_size and holds the cluster; (0, 5]
  double outline_jump = 0.15;
  /// a reported cluster's identity is judged again once it has passed the filters this many
  /// scans in a row with its size settled, and relabeled if another object (or a new one) fits
  /// better: the robot has then seen enough of it to tell its size. 10 scans (2 s at 5 Hz):
  /// 8 to 15 all meet the bundled scenarios' identity floors, 5 does not; [1, 1000]
  int confirm_scans = 10;
  double settle_size = 0.02;  ///< [m] see confirm_scans; [0, 1]
  /// [m] D cells this close to a cell S does not hold free (wall, unknown) are wall noise:
  /// grazing beams free the cells along walls, then hits there feed D. On real logs, walls and
  /// furniture legs are registered to a few centimetres only: with 0.1 m, clusters beside them
  /// "moved" again and again (Freiburg 079, report_errors 2: 30 objects, 84 moves; 0.15 m: 18
  /// and 45). Objects 5 cm from a wall are still found at 0.15 m, not at 0.2 m (their back
  /// cells go); [0, 1]
  double wall_hug_distance = 0.15;
  double thin_width = 0.02;  ///< [m] clusters thinner than this (std across their axis)...; [0, 1]
  double thin_length =
      0.15;  ///< [m] ...and at least this long, next to a wall, are wall noise; [0, 20]
  /// [m] identity by size: sizes closer than this may be the same object. Sizes fitted to the
  /// laser's hit points come within 2 cm of the truth, so 6 cm tells objects 10 cm apart in
  /// size; (0, 5]
  double size_tolerance = 0.06;
  double reappear_distance =
      0.3;  ///< [m] back within this of its last place: reappeared, not moved; (0, 10]
  double follow_margin =
      0.2;  ///< [m] a new cluster within an object's radius + this continues it; [0, 5]
  double move_distance =
      0.3;  ///< [m] a present object whose centre drifts this far has moved; (0, 10]
  /// [s] a cluster whose only size match is an object still shown at a place now out of sight
  /// may wait this long for that place to be seen (free: moved; occupied: a new object). After
  /// that, or at once with 0, it is taken for that object moved and the old place is kept to be
  /// checked when next seen (occupied there: that one is another object). With sizes fitted to
  /// the hit points 0 is right on the bundled scenarios; a wait lets a detection linger as a
  /// ghost of a place the object has since left; [0, 1e6]
  double defer_s = 0.0;
  /// [s] a present object seen at its place less than this long ago (and not seen gone) is no
  /// candidate for a move made out of sight: it did not cross the room in that time. 10 to 60
  /// all keep the bundled scenarios' floors; 0 takes any such object for moved; [0, 1e6]
  double min_unseen_s = 30.0;
  /// [s] a new object (never moved, never back) whose place is seen empty sooner than this
  /// after it was reported rested too briefly to be a moved object: someone who paused, a wall
  /// seen for a moment past people who hid it. It is retracted, not left in the table as absent
  /// (a standing robot's log with people walking past held such an object for 3.9 s). 5 s
  /// changes no figure of the simulated worlds or of the real scans with added objects; 10 s
  /// retracted a cylinder moved again soon after on Freiburg 079. 0 keeps every report; [0, 1e6]
  double min_rest_s = 5.0;
  double match_time_scale = 60.0;  ///< [s] among similar sizes, a vanishing this much older costs
                                   ///< as much as size_tolerance; > 0
  double match_distance_scale =
      10.0;  ///< [m] likewise for the distance from the object's last place; > 0
  /// [m] a known object farther than this from a detection is taken for it only when its size
  /// is the nearest to the detection's of all known objects, by far_size_margin: in a building
  /// full of things of one size a match across it is a guess. 10 m keeps every move of the
  /// bundled scenarios (up to 26 m across corridors, sizes 0.1 m apart) and cuts Freiburg 079's
  /// moves of more than 10 m from 23 to 6; (0, 1e9]
  double far_match_distance = 10.0;
  /// [m] see far_match_distance: sizes fitted to hit points are good to about 2 cm, so another
  /// object less than this farther in size could as well be the one; [0, 5]
  double far_size_margin = 0.02;
  int min_fit_cells = 6;  ///< a circle fit needs this many cells (or hit points), else the
                          ///< size is their width; [3, 1000]

  /// Every key of [objects]: name, member, range, unit, meaning (see OptionTable).
  static const OptionTable<ObjectOptions>& table();
  /// Strict load of [objects]: unknown keys, malformed or out-of-range values throw ConfigError.
  void load(const IniFile& ini);
  /// Throws ConfigError ("<source>: [objects] key: why") for the first rule broken.
  void validate(const std::string& source) const;
  /// Writes the section, one key per line with its meaning (reloadable).
  void writeIni(std::ostream& out) const;
};

}  // namespace dynamap
