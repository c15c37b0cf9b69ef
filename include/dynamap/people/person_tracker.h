#pragma once
// PersonTracker: multi-target tracking of the people the detector sees.
//
// Each track is a constant-velocity Kalman filter (state x y vx vy). Per scan every track is
// predicted to the scan's time, detections farther than `gate` from a prediction are ruled out,
// and the remaining pairs are assigned globally at minimum total distance (the Hungarian
// method); unassigned detections start tentative tracks (but a leg alone beside a person
// detected this scan is one of theirs: legOfPerson).
//
// Life of a track: Tentative (new; must keep moving for confirm_s and go confirm_travel from
// where it appeared; confirm_static_s when it appeared next to an object, or next to an object's
// track that broke off: a moved object glides out of its place for a few seconds and then
// stays, a person walks on; but confirm_s again once it was often seen as a pair of legs
// (TentativeState::mostlyLegs) and the pair itself went confirm_travel: a moved object is one
// cluster) -> Confirmed (a person, with an id) -> Coasting (not detected this
// scan) -> Lost -> Ended. A coasting person who was standing (slower than moving_speed) whose
// place the scan shows occupied (a beam ends within hold_radius) is held: a person who stopped
// keeps their id, however long, until they walk on (a detection again) or their place is seen
// empty for empty_scans scans. A walker is never held so: a beam ending on their prediction is a
// wall they would walk into, or someone else. One who went out of view standing is kept,
// unreported, until detected there again, their place seen empty, or lost_s. Out of view past
// coast_s (walking), or seen empty, a person is Lost: kept lost_s, and a track confirmed within
// reach of where they were last detected (reid_distance, and gate + max_speed x the time since)
// takes their id back, the nearest such person first; such a track is confirmed after
// reacquire_s and reacquire_travel, if it appeared where the scan before saw or within
// reacquire_unseen_speed's reach (else by walking, as a new person, and re-identified then).
// One who went out of view standing and whose id went so to someone else gets it back when
// they walk off from their place (takeBack).

#include <cstddef>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "dynamap/base/share_average.h"
#include "dynamap/people/people_options.h"
#include "dynamap/people/person_detector.h"

namespace dynamap {

/// A constant-velocity Kalman filter in the plane.
class ConstantVelocityFilter {
 public:
  ConstantVelocityFilter(double x, double y, double position_std, double velocity_std);
  /// Moves the state dt seconds ahead; accel_std [m/s^2] is the white-acceleration noise.
  void predict(double dt, double accel_std);
  /// Corrects with a position measured with std `measurement_std`.
  void update(double x, double y, double measurement_std);
  /// Sets the velocity (and its uncertainty) to zero: a person seen standing.
  void stop(double velocity_std);
  double x() const { return s_(0); }
  double y() const { return s_(1); }
  double vx() const { return s_(2); }
  double vy() const { return s_(3); }

 private:
  Eigen::Vector4d s_;
  Eigen::Matrix4d p_;
};

/// The states of a track, each with what only it needs.
struct TentativeState {
  double moving_since_t = 0;  ///< it has been moving since then, without a pause
  double from_x = 0, from_y = 0;  ///< where it was then
  bool near_static = false;       ///< appeared near an object (or took over from one): confirm_static_s
  double born_t = 0;              ///< first detected
  double born_x = 0, born_y = 0;  ///< ...there
  int detections = 0;             ///< detections so far
  int leg_pairs = 0;              ///< ...of which were a pair of legs
  int shaped = 0;                 ///< ...of which the leg classifier saw as a pair of legs
  /// The scan before the first detection saw its place (empty, or a body there not yet
  /// detected, within hold_radius of it): it came into view, rather than the view coming to it
  /// (reacquire_unseen_speed).
  bool in_view_before = false;
  /// Where it was seen as a pair of legs first since it has been moving, and last: a pair that
  /// moves, not a track jumping between two legs (or two small objects) seen one at a time.
  bool pair_seen = false;
  double pair_from_x = 0, pair_from_y = 0, pair_x = 0, pair_y = 0;
  /// Seen as a pair of legs in more than a third of its detections, over kLegsSeen or more: a
  /// person walking across the beams hides one leg behind the other about half the time, and
  /// one walking along a wall is seen from a grazing angle, so "more often than not" missed
  /// real walkers; a moved object is one cluster and is never a pair on its own.
  bool mostlyLegs() const { return detections >= kLegsSeen && 3 * leg_pairs > detections; }
  static constexpr int kLegsSeen = 3;
};
struct ConfirmedState {};
struct CoastingState {
  double since_t = 0;   ///< last detected
  int empty_scans = 0;  ///< consecutive scans that saw its place empty
  bool held = false;    ///< this scan saw its place occupied
  /// Went out of view standing: kept (not reported) until a detection, their place seen empty,
  /// or lost_s; a beam ending there is not taken for them.
  bool unseen_standing = false;
};
/// A person no longer followed (out of view past coast_s, or their place seen empty), kept
/// lost_s so that a new track starting within reid_distance of where they were last detected
/// takes their id back instead of a new one: people who leave the sensor's view and come back
/// keep their identity.
struct LostState {
  double since_t = 0;
};
struct EndedState {
  double t = 0;
};
enum class PersonState { Tentative, Confirmed, Coasting, Lost, Ended };
const char* toString(PersonState s);

struct PersonTrack {
  int key = 0;  ///< internal, in order of creation
  int id = 0;   ///< person id once confirmed (1, 2, ...), 0 while tentative
  ConstantVelocityFilter filter;
  std::variant<TentativeState, ConfirmedState, CoastingState, LostState, EndedState> state;
  double last_detected_t = 0;
  double detected_x = 0, detected_y = 0;  ///< the filter's position at its last detection
  double first_reported_t = 0, last_reported_t = 0;
  double path_length = 0;  ///< [m] along its reported positions
  double last_x = 0, last_y = 0;

  PersonState kind() const { return static_cast<PersonState>(state.index()); }
  /// Confirmed, or coasting after having been confirmed: a person where the tracker follows them.
  bool isPerson() const {
    return id != 0 && kind() != PersonState::Ended && kind() != PersonState::Lost;
  }
};

/// One row of people.csv.
struct PersonRow {
  int person_id;
  double x, y, vx, vy;
};

/// Where a person walked, for pictures: a point each time they moved kTrailStep from the last.
struct PersonTrail {
  int id = 0;
  std::vector<std::pair<double, double>> points;
};

/// Per-person figures for summary.json.
struct PersonSummary {
  int id;
  double first_t, last_t;
  double path_length;
};

class PersonTracker {
 public:
  explicit PersonTracker(const PeopleOptions& options = {});

  /// The per-scan step with this scan's detections and its hits (for "is the place seen"), and
  /// the share of its hits in S's free space (detectPeople): while that share, averaged over
  /// the last scans, is above max_free_share the map does not hold still, motion in it means
  /// nothing, and only the leg classifier's shape confirms a person.
  void update(const std::vector<PersonDetection>& detections, const ScanHits& hits, double t,
              double free_share = 0);
  /// Whether the map held still at the last update (see update).
  bool mapSteady() const { return free_share_.value() <= options_.max_free_share; }

  /// The people to report for the last scan: confirmed tracks and held (stopped) people, by id.
  std::vector<PersonRow> reported() const;
  /// Every track alive (not ended), tentative and lost ones included.
  const std::vector<PersonTrack>& tracks() const { return tracks_; }
  /// Every person ever confirmed, by id (ended ones included).
  std::vector<PersonSummary> summaries() const;
  /// Every person's trail, by id (ended ones included). At most kMaxTrailPoints points in all:
  /// past that, trails stop growing (the pictures of a very long run show its start).
  std::vector<PersonTrail> trails() const;
  static constexpr double kTrailStep = 0.1;              // [m]
  static constexpr std::size_t kMaxTrailPoints = 200000;
  /// A track confirmed in the last update that stood next to an object when it appeared
  /// (near_static): where it stood (when it appeared, and before it last set off) and since
  /// when. What was reported as an object there may have been this person.
  struct WalkOff {
    double born_x, born_y, from_x, from_y, since_t;
  };
  const std::vector<WalkOff>& walkOffs() const { return walk_offs_; }
  /// Where a pair of legs stands that is no person yet: tentative tracks detected in the last
  /// update, seen mostly as two legs (TentativeState::mostlyLegs).
  std::vector<std::pair<double, double>> standingLegs() const;
  /// Where people are now (confirmed or coasting): no object may be reported there.
  std::vector<std::pair<double, double>> personPositions() const;
  const PeopleOptions& options() const { return options_; }

 private:
  void predictAll(double t);
  std::vector<int> associate(const std::vector<PersonDetection>& detections) const;
  void correct(PersonTrack& tr, const PersonDetection& d, double t);
  void miss(PersonTrack& tr, const ScanHits& hits, double t);
  void coastUnseen(PersonTrack& tr, CoastingState& st, double t);
  void advanceTentative(PersonTrack& tr, double t);
  void endTrack(PersonTrack& tr, double t);
  void loseTrack(PersonTrack& tr, double t);
  /// The lost person a track confirmed now at (x, y) is (nearest last detection within reach),
  /// or nullptr: a new person.
  PersonTrack* reidentify(double x, double y, double t);
  /// Whether a tentative track `st` is `lost` (reidentify's choice, or nullptr) back in view
  /// soon enough to take the quick route (reacquire_unseen_speed).
  bool backInView(const TentativeState& st, const PersonTrack* lost) const;
  void confirm(PersonTrack& tr, double t);
  /// Someone went out of view standing, and re-identification gave their id to another track
  /// (nobody saw their place empty: they may as well still be there). Until their place is
  /// seen empty, or lost_s, a track confirmed that appeared within kTakeBackGates gates of it
  /// (and nearer than `lost`'s last detection, re-identification's choice) is them walking off:
  /// it takes the id back (and that track's figures so far), and the track that had it goes on
  /// under a new id. True when so; `tr` is left to confirm() to confirm.
  bool takeBack(PersonTrack& tr, const PersonTrack* lost, double t);
  /// A break in id's trail (none drawn across where they were unseen, or from someone else's).
  void breakTrail(int id);
  /// Gives `tr` the next id, a trail of its own and figures from t on.
  void newId(PersonTrack& tr, double t);
  struct StoodUnseen {
    int id;
    double x, y;  // their last detection
    double t;     // ...when
  };
  std::vector<StoodUnseen> stood_unseen_;
  void record(PersonTrack& tr, double t);

  PeopleOptions options_;
  std::vector<PersonTrack> tracks_;  // alive, by key
  /// Near a track that went near_static, a new track is near_static too: a gliding object
  /// whose track broke off must not restart as a person. (x, y, t) of where such tracks ended.
  bool nearStaticTrack(double x, double y, double t) const;
  void startTrack(const PersonDetection& d, double t);
  /// A leg alone within half leg_pair_distance of a person detected this scan is one of their
  /// legs that the pairing left over (two people passing close, a leg seen twice), not a new
  /// person: two walkers crossing made a third track of such legs, which took a lost id.
  bool legOfPerson(const PersonDetection& d, double t) const;
  struct StaticEnd {
    double x, y, t;
  };
  std::vector<StaticEnd> static_ends_;
  std::vector<WalkOff> walk_offs_;  // of the last update
  std::vector<PersonSummary> ended_;
  std::vector<PersonTrail> trails_;  // by id: trails_[id - 1]
  std::size_t trail_points_ = 0;
  bool have_t_ = false;
  double last_t_ = 0;
  ShareAverage free_share_;  // of the scans so far
  /// The scan before this one (TentativeState::in_view_before); before the first, no beam:
  /// every place unseen.
  ScanHits last_hits_;
  int next_key_ = 1;
  int next_id_ = 1;
};

/// What a scan shows of the disc (x, y, r): Occupied when a beam ends in it, Empty when beams
/// cross it without ending there, Unseen when none reaches it.
enum class DiscView { Unseen, Empty, Occupied };
DiscView viewDisc(const ScanHits& hits, double x, double y, double r);

}  // namespace dynamap
