#pragma once
// Options of the people tracker (section [people]): how the scan's hit points in the static
// map's free space become person detections, and how detections become tracks.

#include <iosfwd>
#include <string>

#include "dynamap/base/option_table.h"

namespace dynamap {

/// Section [people]. Lengths in metres, times in seconds.
struct PeopleOptions {
  static constexpr const char* kSection = "people";

  bool enabled = true;            ///< track people at all (false: people.csv has only its header)
  double cluster_distance = 0.1;  ///< [m] consecutive hit points this close form one cluster; (0, 1]
  int min_points = 2;             ///< a cluster of fewer hit points is no detection; [1, 100]
  double max_leg_width = 0.25;    ///< [m] clusters up to this wide are legs (paired); (0, 2]
  double max_person_width = 0.8;  ///< [m] wider clusters are not a person; [max_leg_width, 5]
  double leg_pair_distance = 0.8;  ///< [m] two legs whose centres are this close are one person; [0, 2]
  int wall_guard_cells = 1;       ///< a hit with a cell S does not hold free this near is no detection; [0, 5]
  /// Legs are also recognised by their shape in the scan itself (leg_classifier.h), wherever S
  /// does not hold the cluster occupied: people in space S has not seen free yet, and on a
  /// robot whose poses drift. Such a detection starts a track like any other.
  bool leg_classifier = true;
  std::string leg_model;          ///< "" = the model built into dynamap, else a file of dynamap train-legs
  double leg_probability = 0.5;   ///< a cluster the classifier gives at least this is a leg; [0, 1]
  double gate = 0.6;              ///< [m] a detection farther than this from a track's prediction never updates it; (0, 5]
  double accel_std = 1.0;         ///< [m/s^2] the constant-velocity model's process noise; (0, 100]
  double measurement_std = 0.1;   ///< [m] a detection's position noise; (0, 1]
  /// [s] a new track is a person once it has kept moving (moving_speed) this long without a
  /// pause; [0, 600]
  double confirm_s = 0.6;
  /// [s] ...this long when it appeared within static_clearance of a cell S holds occupied: an
  /// object that stood in S and is moved away glides a few seconds and stays, a person walks
  /// on; [confirm_s, 600]
  double confirm_static_s = 6.0;
  double static_clearance = 0.35;  ///< [m] see confirm_static_s; [0, 2]
  /// [m] a body S holds occupied counts for confirm_static_s when it fits in a square this
  /// wide (something that can be moved); larger ones are walls, which people walk along; [0, 10]
  double object_max_extent = 1.2;
  /// [m] ...or, whatever its size, when the track's detections see through static_left_cells
  /// cells S holds occupied within static_clearance, their beams ending this far beyond them:
  /// something that stood there has left (an object 5 cm from a wall is one body with the wall
  /// in S, but the wall is never seen through). Far above the cell size, so that a wall seen at
  /// a grazing angle, whose cells a beam may clip, does not count; (0, 10]
  double static_left_margin = 0.3;
  int static_left_cells = 3;  ///< see static_left_margin; [1, 1000]
  double moving_speed = 0.25;     ///< [m/s] slower than this a track is not moving; [0, 10]
  double confirm_travel = 0.5;    ///< [m] ...and has gone this far from where it appeared; [0, 100]
  /// A new track is a person, moving or not, once the leg classifier has seen it as a pair of
  /// legs in this many scans and in more than half of its detections; 0 = never; [0, 1000]
  int shape_confirm_scans = 10;
  /// While more than this share of the scans' hits (averaged over the last few) lands in space
  /// S holds free, the map does not hold still (poses off, or a moving robot mapped with fixed
  /// poses): only shape_confirm_scans confirms; [0, 1]
  double max_free_share = 0.5;
  double tentative_miss_s = 0.6;  ///< [s] a tentative track unseen this long ends; (0, 60]
  double coast_s = 4.0;           ///< [s] a person walking out of view is lost after this long; (0, 600]
  double hold_radius = 0.15;      ///< [m] a beam ending this near a lost person holds them; [0, 2]
  double lost_s = 60.0;           ///< [s] a lost person's id can be given back this long, and one who went out of view standing is kept this long; 0 = never; [0, 3600]
  double reid_distance = 50.0;    ///< [m] ...to a new track confirmed this near their last detection; [0, 100]
  double max_speed = 2.0;         ///< [m/s] ...and within gate + max_speed x time since; (0, 20]
  /// [s] a new track within reid_distance of a lost person (and not near an object) is that
  /// person once it has kept moving this long; [0, confirm_s]
  double reacquire_s = 0.2;
  double reacquire_travel = 0.25;  ///< [m] ...and gone this far; [0, confirm_travel]
  /// [m/s] ...but one that appeared where the scan before did not see (the view came to it, not
  /// it into view) only within gate + this x the time the person was unseen: someone who stood
  /// or lingered out of view. Farther, a body that was there all along (an object the robot
  /// turns to) would take the id of anyone lost within walking reach; it is confirmed by walking
  /// (confirm_s, confirm_travel) instead, and re-identified then; [0, max_speed]
  double reacquire_unseen_speed = 0.3;
  int empty_scans = 3;            ///< a lost person's place seen empty this many scans in a row ends them; [1, 1000]
  /// [m] no object is confirmed this near a person (confirmed, or held standing): their legs
  /// are no object; one put down beside them is judged once they have left. 0 = off; [0, 5]
  double exclusion_radius = 0.5;

  /// Every key of [people], declared once (config.ini, default.ini and the README follow it).
  static const OptionTable<PeopleOptions>& table();
  /// Strict load of [people]: unknown keys, malformed or out-of-range values throw ConfigError.
  void load(const IniFile& ini);
  /// Throws ConfigError ("<source>: [people] key: why") for the first rule broken.
  void validate(const std::string& source) const;
  /// Writes the section, one key per line with its meaning (reloadable).
  void writeIni(std::ostream& out) const;
};

}  // namespace dynamap
