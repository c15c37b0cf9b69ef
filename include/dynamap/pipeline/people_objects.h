#pragma once
// PeopleObjects: takes out of the object table what was a person standing still.
//
// To the dynamic map a person who stands is an object like any other: D's cells pass the
// threshold where S knows the floor free, and the object tracker reports them within
// confirm_scans (a person seen at leg height: two small objects). No single scan tells them
// apart; what follows does. Each place an object is reported at (new, moved, reappeared) is a
// person's when
//  - standing legs: a tentative track seen as a pair of legs stands within static_clearance
//    (PersonTracker::standingLegs), or the object is leg-sized (max_leg_width) and another
//    leg-sized object is reported within kPairWindowS and leg_pair_distance of it (two legs
//    side by side), or it is leg-sized and within half leg_pair_distance of an object
//    withdrawn before (people stand where people stood);
//  - walk-off: the people tracker confirms a track that appeared next to an object (it stood
//    there first) within static_clearance of the place, reported there since that track
//    appeared, and the object goes within kWalkOffWindowS of the confirmation (either side);
//  - leg pair: it is leg-sized, and it and another leg-sized object within leg_pair_distance
//    go from their places within kPairWindowS of each other.
// An object whose every place was a person's is withdrawn (ObjectTracker::withdraw: out of
// objects.csv and events.csv) when it goes from its place. One still in its place never is:
// what a person stood next to stays, two small objects put down side by side stay, and a person
// still standing when the log ends stays in the table too (nothing tells them from such a pair).
//
// Per scan the cost is bounded by the scan's object events and walk-offs, the standing legs
// and the objects that went in the last kWalkOffWindowS: it does not grow with the run's length.

#include <cstddef>
#include <deque>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dynamap/objects/object_tracker.h"
#include "dynamap/people/people_options.h"
#include "dynamap/people/person_tracker.h"

namespace dynamap {

class PeopleObjects {
 public:
  explicit PeopleObjects(const PeopleOptions& options) : options_(options) {}

  /// After the people and the object tracker's update of a scan at time t; the object events
  /// from index `first_event` on are this scan's.
  void update(const PersonTracker& people, ObjectTracker& objects, std::size_t first_event,
              double t, std::size_t scan_index);

  static constexpr double kWalkOffWindowS = 10.0;
  static constexpr double kPairWindowS = 2.0;

 private:
  struct Place {
    double x, y, since_t, until_t;
  };
  /// An object reported (or gone) at (x, y) with its size, at time t.
  struct Sighting {
    int id;
    double t, x, y, size;
  };
  /// The places an object was reported at (new, moved, reappeared), and how many of them a
  /// person's: one whose every place was is withdrawn once it goes.
  struct Record {
    int placements = 0, person_like = 0;
    double placed_t = 0;  ///< when it was reported at its present place
    bool current_person_like = false;
  };
  void placed(const PersonTracker& people, const Sighting& s);
  void markPersonLike(int id);
  bool allPersonLike(int id) const;
  void addWalkOffs(const PersonTracker& people, ObjectTracker& objects, double t,
                   std::size_t scan_index);
  void judgeGone(ObjectTracker& objects, const Sighting& g, std::size_t scan_index);
  /// Its present place is where a track that walked off as a person stood, since before.
  bool walkedOff(const Sighting& g) const;
  bool legSized(double size) const { return size <= options_.max_leg_width; }
  /// Withdraws `id` and drops it from what this class remembers.
  void withdraw(ObjectTracker& objects, int id, double t, std::size_t scan_index);

  PeopleOptions options_;
  std::vector<Place> walk_offs_;  // within their window
  std::deque<Sighting> gone_;     // objects gone in the last kWalkOffWindowS, not withdrawn
  std::deque<Sighting> fresh_;    // leg-sized objects reported in the last kPairWindowS
  std::unordered_map<int, Record> records_;  // by object id
  /// Where withdrawn objects stood, by cells leg_pair_distance wide (at most kPlacesPerCell
  /// each: a checked place costs the same however long the run).
  std::unordered_map<CellKey, std::vector<std::pair<double, double>>> person_places_;
  static constexpr std::size_t kPlacesPerCell = 8;
  CellKey placeCell(double x, double y) const;
  bool nearPersonPlace(double x, double y) const;
};

}  // namespace dynamap
