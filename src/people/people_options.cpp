#include "dynamap/people/people_options.h"

#include <ostream>

#include "dynamap/base/ini.h"

namespace dynamap {

namespace {

using O = PeopleOptions;

// The keys of the detector: which hits make a person.
std::vector<Option<O>> detectorRows() {
  return {
      {"enabled", &O::enabled, {}, "", "track people at all (false: people.csv holds only its header)"},
      {"cluster_distance", &O::cluster_distance, Range::openClosed(0, 1), "m",
       "consecutive hit points this close form one cluster"},
      {"min_points", &O::min_points, Range::closed(1, 100), "", "fewer hit points is no detection"},
      {"max_leg_width", &O::max_leg_width, Range::openClosed(0, 2), "m",
       "clusters up to this wide are legs"},
      {"max_person_width", &O::max_person_width, Range::closed(0, 5), "m",
       "wider clusters are no person (at least max_leg_width)"},
      {"leg_pair_distance", &O::leg_pair_distance, Range::closed(0, 2), "m",
       "two legs this close (centres) are one person"},
      {"wall_guard_cells", &O::wall_guard_cells, Range::closed(0, 5), "",
       "a hit this many cells near a cell S does not hold free is no detection"},
      {"leg_classifier", &O::leg_classifier, {}, "",
       "also take clusters shaped like legs (a classifier trained on real laser data) where S does not hold them occupied"},
      {"leg_model", &O::leg_model, {}, "",
       "the classifier: empty = the one built into dynamap, else a file written by dynamap train-legs"},
      {"leg_probability", &O::leg_probability, Range::closed(0, 1), "",
       "a cluster the classifier gives at least this is a leg"},
  };
}

// The keys of the tracker: gates, confirmation, coasting, identities.
std::vector<Option<O>> trackerRows() {
  return {
      {"gate", &O::gate, Range::openClosed(0, 5), "m",
       "a detection farther than this from a track's prediction never updates it"},
      {"accel_std", &O::accel_std, Range::openClosed(0, 100), "m/s^2",
       "the constant-velocity model's process noise"},
      {"measurement_std", &O::measurement_std, Range::openClosed(0, 1), "m",
       "detection noise (twice this for a leg seen alone)"},
      {"confirm_s", &O::confirm_s, Range::closed(0, 600), "s",
       "a new track is a person after moving this long without a pause"},
      {"confirm_static_s", &O::confirm_static_s, Range::closed(0, 600), "s",
       "...this long when it appeared near an object (D's object cells, a small body of S; at least confirm_s), unless seen as two legs"},
      {"static_clearance", &O::static_clearance, Range::closed(0, 2), "m",
       "...this near (objects reported this near where such a track stood, gone when it walked off, were it)"},
      {"object_max_extent", &O::object_max_extent, Range::closed(0, 10), "m",
       "...of a body S holds that fits in a square this wide (larger ones are walls)"},
      {"static_left_margin", &O::static_left_margin, Range::openClosed(0, 10), "m",
       "...or of any body S holds, seen through by beams ending this far beyond its cells (it left)"},
      {"static_left_cells", &O::static_left_cells, Range::closed(1, 1000), "",
       "...this many of its cells"},
      {"moving_speed", &O::moving_speed, Range::closed(0, 10), "m/s",
       "a track slower than this is not moving"},
      {"confirm_travel", &O::confirm_travel, Range::closed(0, 100), "m",
       "...and it must go this far from where it started moving"},
      {"shape_confirm_scans", &O::shape_confirm_scans, Range::closed(0, 1000), "",
       "...or, moving or not, once the leg classifier saw it as two legs in this many scans (and most of its detections); 0 = never"},
      {"max_free_share", &O::max_free_share, Range::closed(0, 1), "",
       "while more than this share of the last scans' hits lands where S holds free space (the poses are off), only shape confirms"},
      {"tentative_miss_s", &O::tentative_miss_s, Range::openClosed(0, 60), "s",
       "a tentative track unseen this long ends"},
      {"coast_s", &O::coast_s, Range::openClosed(0, 600), "s",
       "a person walking out of view is lost after this long (one standing: lost_s)"},
      {"hold_radius", &O::hold_radius, Range::closed(0, 2), "m",
       "a beam ending this near a lost person holds them (stopped)"},
      {"lost_s", &O::lost_s, Range::closed(0, 3600), "s",
       "a lost person's id is given back this long to a new track near their last detection, and a person who went out of view standing is kept this long; 0 = never"},
      {"reid_distance", &O::reid_distance, Range::closed(0, 100), "m",
       "...this near (the nearest lost person)"},
      {"max_speed", &O::max_speed, Range::openClosed(0, 20), "m/s",
       "...and within gate + this speed times the time since (nobody walks faster)"},
      {"reacquire_s", &O::reacquire_s, Range::closed(0, 600), "s",
       "a new track near a lost person (not near an object) is them after moving this long (at most confirm_s)"},
      {"reacquire_travel", &O::reacquire_travel, Range::closed(0, 100), "m",
       "...and gone this far (at most confirm_travel)"},
      {"reacquire_unseen_speed", &O::reacquire_unseen_speed, Range::closed(0, 20), "m/s",
       "...but one appearing where the scan before did not see, only within gate + this speed times the time the person was unseen (at most max_speed)"},
      {"empty_scans", &O::empty_scans, Range::closed(1, 1000), "",
       "a lost person's place seen empty this many scans in a row ends them"},
      {"exclusion_radius", &O::exclusion_radius, Range::closed(0, 5), "m",
       "no object is confirmed this near a person (their legs); 0 = off"},
  };
}

}  // namespace

const OptionTable<PeopleOptions>& PeopleOptions::table() {
  static const OptionTable<O> t(kSection, [] {
    std::vector<Option<O>> rows = detectorRows();
    for (Option<O>& r : trackerRows()) rows.push_back(std::move(r));
    return rows;
  }());
  return t;
}

void PeopleOptions::load(const IniFile& ini) {
  table().load(ini, *this);
  validate(ini.name());
}

void PeopleOptions::validate(const std::string& src) const {
  table().checkRanges(*this, src);
  if (max_person_width < max_leg_width) {
    rejectValue(src, kSection, "max_person_width", "must be at least max_leg_width");
  }
  if (reacquire_s > confirm_s) rejectValue(src, kSection, "reacquire_s", "must be at most confirm_s");
  if (reacquire_travel > confirm_travel) {
    rejectValue(src, kSection, "reacquire_travel", "must be at most confirm_travel");
  }
  if (reacquire_unseen_speed > max_speed) {
    rejectValue(src, kSection, "reacquire_unseen_speed", "must be at most max_speed");
  }
  if (confirm_static_s < confirm_s) {
    rejectValue(src, kSection, "confirm_static_s", "must be at least confirm_s");
  }
}

void PeopleOptions::writeIni(std::ostream& out) const { table().write(*this, out); }

}  // namespace dynamap
