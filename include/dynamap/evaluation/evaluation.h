#pragma once
// Evaluation against the simulator's ground truth (docs/evaluation.md): the paper's
// Table 3 per object move, detection latency, and static/dynamic cell accuracy of the final maps.
//
// Pure functions over plain data, no I/O: the `dynamap eval` command reads the truth files, the
// tracker's tracks.csv and the gridmaps into these structs, and the tests write them by hand.
// Undefined figures (a percentage of nothing, the median of no latency) are NaN.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "dynamap/base/pose_track.h"
#include "dynamap/sim/world.h"

namespace dynamap {

/// The value of an undefined figure.
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- inputs ----------------------------------------------------------------------------------

/// One row of <name>.objects.csv: where a movable object or a person was at one scan.
struct TruthRow {
  std::size_t scan_index = 0;
  double t = 0;  ///< simulated seconds
  sim::BodyKind kind = sim::BodyKind::Object;
  int id = 0;
  double x = 0, y = 0;
  double diameter = 0;
  int hits = 0;  ///< beams of that scan whose first surface was this body
};

/// One row of <name>.moves.csv.
struct TruthMove {
  int move_id = 0;
  int object_id = 0;
  double t_start = 0, t_end = 0;  ///< simulated seconds
  sim::Vec2 from, to;
};

/// One row of the tracker's tracks.csv. Only scan_index is used to line rows up with the truth
/// (the truth's own time of that scan is used for latency), so `t` may be in any time base.
struct TrackRow {
  std::size_t scan_index = 0;
  double t = 0;
  int object_id = 0;
  double cx = 0, cy = 0;
  double size_m = 0;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
};

/// The thresholds of the definitions; the defaults are the issue's.
struct EvalOptions {
  double min_match_radius_m = 0.25;  ///< a row matches a body within max(this, diameter)
  int min_visible_hits = 3;          ///< beams on the object at its new place to call it visible
  double detect_window_s = 10;       ///< detection must come this soon after visibility...
  /// ...or within this many scans of it, whichever is later: 10 s at the simulator's 5 Hz, and
  /// as many scans on a log whose scans come seconds apart (D needs 5 of them whatever the rate).
  std::size_t detect_window_scans = 50;
  double static_distance_m = 0.5;    ///< farther than this from every body: not a real object
  double place_tolerance_m = 1e-3;   ///< the truth's position "is" the move's target within this
  /// A move seen (min_visible_hits beams) in fewer scans of its window was hardly seen: D needs
  /// five hits in one cell, and at 1 degree and 5-12 m each beam's end falls on another cell of
  /// the arc from scan to scan (explainMisses).
  std::size_t few_views_scans = 15;
};

// --- object level ------------------------------------------------------------------------------

/// A true body: movable object or person, by the scenario's number.
struct BodyKey {
  sim::BodyKind kind = sim::BodyKind::Object;
  int id = 0;
  bool operator<(const BodyKey& o) const { return kind != o.kind ? kind < o.kind : id < o.id; }
  bool operator==(const BodyKey& o) const { return kind == o.kind && id == o.id; }
};

/// A tracker id and the body it matched most often (ties: objects before people, lower id).
struct IdAssignment {
  int track_id = 0;
  std::size_t rows = 0;     ///< rows of this id in tracks.csv
  std::size_t matches = 0;  ///< of them, rows matching `body`; 0: matched nothing, unassigned
  BodyKey body;
  std::size_t far_rows = 0;    ///< rows farther than static_distance_m from every body
  bool static_object = false;  ///< far_rows for most (> half) of its rows
  bool log_own = false;        ///< set aside by setAsideLogOwn (then not static_object)
  bool left_behind = false;    ///< set aside by setAsideLeftBehind (then not static_object)
};

/// Why a move that became visible was not detected (explainMisses): what the result shows at
/// its new place during its detection window, the first of these that holds.
enum class MissCause {
  None,              ///< detected, or never visible
  PersonOnPlace,     ///< a person track stood on it: the people tracker took it for someone
  PeopleNear,        ///< people within kNearRadius of it: they hid it, or their cells joined it
  ReportedOffPlace,  ///< an object was reported within kNearRadius, matching it nowhere
  FewViews,          ///< seen by min_visible_hits beams in fewer than few_views_scans scans
  Unreported,        ///< seen often enough, nothing reported near it
};
/// Every cause but None, in MissCause's order: its key in metrics.json and its words.
struct MissCauseName {
  MissCause cause;
  const char* key;   ///< "person_on_place", "people_near", ...: missed_because, missed_<key>
  const char* text;  ///< "a person track on its place", ...
  const char* row;   ///< "a person on its place", ...: its row of eval --summary (short)
};
extern const MissCauseName kMissCauses[5];
/// The cause's key; nullptr for None.
const char* toString(MissCause c);
/// The cause in words, for reports; "" for None.
const char* describe(MissCause c);

/// What became of one move.
struct MoveResult {
  int move_id = 0, object_id = 0;
  bool visible = false;  ///< false: never seen at its new place (not scored)
  std::size_t visible_scan = 0;
  double visible_t = 0;
  bool matched = false;       ///< some row matched the object at its new place in the window
  bool correct = false;       ///< ... and one of them carried an id assigned to the object
  bool wrong_id = false;      ///< ... a matching row's id is assigned to another body
  bool double_match = false;  ///< at a window scan: two ids on the object, or an id on two bodies
  std::size_t first_correct_scan = 0;
  double latency_s = 0;  ///< first correct row's time - visible_t (when correct)
  std::size_t latency_scans = 0;
  MissCause missed_because = MissCause::None;  ///< set by explainMisses
  bool sizeError() const { return wrong_id || double_match; }
  bool notDetected() const { return visible && !matched; }
};

struct LatencyStats {
  std::size_t count = 0;
  double median_s = 0, max_s = 0;  ///< NaN when count is 0
  double median_scans = 0, max_scans = 0;
};

struct ObjectScores {
  std::vector<MoveResult> moves;  ///< by move id
  std::vector<IdAssignment> ids;  ///< by tracker id
  std::size_t visible = 0;        ///< moves that became visible
  std::size_t correct = 0;        ///< correctly detected
  std::size_t not_detected = 0;
  std::size_t size_errors = 0;        ///< moves with a size estimation error (may also be correct)
  std::size_t static_as_objects = 0;  ///< tracker ids that are mostly far from every body
  /// Tracker ids (not static) whose rows match a person most often: someone standing, reported
  /// as an object (the final table only: eval leaves withdrawn objects out).
  std::size_t people_as_objects = 0;
  /// Real scans with added objects: ids set aside by setAsideLogOwn (not counted as static).
  std::size_t log_own_objects = 0;
  /// Real scans: ids set aside by setAsideLeftBehind (not counted as static).
  std::size_t left_behind_objects = 0;
  LatencyStats latency;
};

/// Whether the scan `scan` at time `t` lies in the detection window of the visible move `r`: from
/// its visible scan to detect_window_s later, or to detect_window_scans scans later, whichever
/// is later.
bool inDetectWindow(const MoveResult& r, std::size_t scan, double t, const EvalOptions& options);

/// Matches, in the definitions' sense: the row's centre within max(min radius, diameter) of the
/// body's centre.
bool rowMatches(const TrackRow& row, const TruthRow& body, const EvalOptions& options);
/// Distance from the row's centre to the body's disc (0 inside it).
double distanceToBody(const TrackRow& row, const TruthRow& body);
/// Median of `v` (the mean of the two middle values for an even count); NaN when empty.
double median(std::vector<double> v);

/// Scores every move of `moves` and every tracker id of `tracks` against the truth `rows`.
/// Throws std::invalid_argument when a track row names a scan the truth does not have.
ObjectScores evaluateObjects(const std::vector<TruthRow>& rows, const std::vector<TruthMove>& moves,
                             const std::vector<TrackRow>& tracks, const EvalOptions& options = {});

/// One row of the tracker's people.csv.
struct PersonTrackRow {
  std::size_t scan_index = 0;
  int person_id = 0;
  double x = 0, y = 0;
};

/// Sets missed_because of every move of `scores` (evaluateObjects' of `rows` and `moves`) that
/// became visible and was not detected, from the result's object `tracks` and its `people`
/// (MissCause, in its order), over the scans of its window where the object stands at its new
/// place: a person track on the place (within the object's radius + kOnPlaceMargin) or people
/// within kNearRadius count on kPeopleScans or more of them.
void explainMisses(ObjectScores& scores, const std::vector<TruthRow>& rows,
                   const std::vector<TruthMove>& moves, const std::vector<TrackRow>& tracks,
                   const std::vector<PersonTrackRow>& people, const EvalOptions& options = {});
constexpr double kOnPlaceMargin = 0.15;  // [m]
constexpr double kNearRadius = 1.0;      // [m]
constexpr std::size_t kPeopleScans = 5;

/// Where the mapper reported an object on a real log before objects were added to it (perturb
/// --add-objects' NAME.own.csv): the log's own changes (people, doors, chairs), which no truth
/// labels.
struct OwnRow {
  std::size_t scan_index = 0;
  double x = 0, y = 0;
};

/// Sets aside every id counted as a static part whose rows, for more than half of them, lie within
/// `radius` of a place an own row stood at, at their scan or before: it is the log's own change
/// (log_own, not static_object; the counts follow). Not only the same scan: how long the table
/// keeps such an object, or which detection later takes its id, depends on the other objects
/// in it, and nothing labels the log's own changes to say which story is right.
void setAsideLogOwn(ObjectScores& scores, const std::vector<TrackRow>& tracks,
                    const std::vector<OwnRow>& own, double radius = 0.5);

/// Sets aside every id counted as a static part whose rows, for more than half of them, lie
/// where an object of `rows` stood at or before their scan (within max(min_match_radius_m, its
/// diameter)): the table keeps an object where it last saw it until the place is seen empty, and
/// a robot that never looks back leaves it there (left_behind, not static_object).
void setAsideLeftBehind(ObjectScores& scores, const std::vector<TrackRow>& tracks,
                        const std::vector<TruthRow>& rows, const EvalOptions& options = {});

// --- cell level --------------------------------------------------------------------------------

/// A grid's geometry, MRPT's convention: cell (ix, iy) covers [x_min + ix·res, x_min + (ix+1)·res)
/// × [y_min + iy·res, ...); cells are stored row by row, index ix + iy·size_x.
struct GridGeometry {
  double x_min = 0, y_min = 0;
  double resolution = 0.05;
  int size_x = 0, size_y = 0;
  std::size_t cells() const { return static_cast<std::size_t>(size_x) * size_y; }
  std::size_t index(int ix, int iy) const { return static_cast<std::size_t>(iy) * size_x + ix; }
};

using CellMask = std::vector<std::uint8_t>;  ///< one flag per cell, GridGeometry's order

/// The true cells on a grid (see docs/evaluation.md).
struct CellTruth {
  CellMask static_cells;   ///< cells a wall covers
  CellMask dynamic_cells;  ///< covered by a person, or an object from its first move, no wall
  CellMask world_at_end;   ///< walls and every body at the last scan of the truth
};

/// Cells whose closed square the segment touches.
void rasteriseSegment(const sim::Segment& s, const GridGeometry& g, CellMask& mask);
/// Cells whose square overlaps a wall pixel of the image's grid (interiors overlap).
void rasteriseWallGrid(const sim::WallGrid& walls, const GridGeometry& g, CellMask& mask);
/// Cells whose square overlaps the open disc.
void rasteriseDisc(sim::Vec2 centre, double radius, const GridGeometry& g, CellMask& mask);

/// The truth of `world` and of the bodies in `rows` (moves give each object's first move).
CellTruth cellTruth(const sim::StaticWorld& world, const std::vector<TruthRow>& rows,
                    const std::vector<TruthMove>& moves, const GridGeometry& g);

/// SA/DA/AA/HA of one static map, in percent.
struct CellScores {
  std::size_t static_cells = 0, static_kept = 0;     ///< observed static truth; of them kept
  std::size_t dynamic_cells = 0, dynamic_clear = 0;  ///< observed dynamic truth; of them clear
  double sa = 0, da = 0, aa = 0, ha = 0;
};

/// Scores a static map given as P(occupied) per cell, over the `observed` cells only.
CellScores scoreStaticMap(const std::vector<float>& s_occ, const CellTruth& truth,
                          const CellMask& observed, const GridGeometry& g);

/// Precision and recall of occupied cells (percent), with the SA rule's one-cell tolerance: a
/// predicted cell is right when a true cell is it or a 4-neighbour, a true cell is found when a
/// predicted cell is it or a 4-neighbour.
struct PrecisionRecall {
  std::size_t predicted = 0, predicted_right = 0;
  std::size_t truth = 0, truth_found = 0;
  double precision = 0, recall = 0;
};
PrecisionRecall scoreOccupied(const CellMask& predicted, const CellMask& truth,
                              const CellMask& observed, const GridGeometry& g);

/// S ∪ D as occupied cells: S P(occ) > 0.5 or D P(occ) > object_threshold.
CellMask unionOccupied(const std::vector<float>& s_occ, const std::vector<float>& d_occ,
                       double object_threshold);

/// Cells observed at least once: some layer's P(occ) is off the 0.5 prior.
CellMask observedCells(const std::vector<const std::vector<float>*>& layers);

// --- trajectory level ------------------------------------------------------------------------

/// The pose of `poses` (sorted by time) whose timestamp is nearest `t`, within `tolerance`
/// seconds (the earlier of two as near); nullptr when none is.
const TimedPose* poseAtTime(const std::vector<TimedPose>& poses, double t, double tolerance);

/// Absolute trajectory error of an estimate against the truth.
struct TrajectoryError {
  std::size_t matched = 0;    ///< estimated poses with a truth pose at their timestamp
  std::size_t unmatched = 0;  ///< estimated poses without one (not scored)
  double rmse_xy_m = 0;       ///< RMSE of the position error; NaN when nothing matched
  double rmse_phi_rad = 0;    ///< RMSE of the heading error (wrapped to [-pi, pi])
  double max_xy_m = 0;        ///< largest position error
};

/// Pairs each estimated pose with the truth pose of the same timestamp (within
/// `time_tolerance_s`; `truth` sorted by time) and scores them. The estimate is first anchored
/// at the truth: its first matched pose is moved onto the truth's, and every other pose with it
/// (a rigid SE(2) transform), so an estimate in its own frame (a SLAM run starting at the
/// origin) is scored like one in the truth's frame; an estimate that starts on the truth, as
/// dynamap's do, is unchanged.
TrajectoryError trajectoryError(const std::vector<TimedPose>& estimate,
                                const std::vector<TimedPose>& truth,
                                double time_tolerance_s = 1e-3);

/// Trajectory errors that do not depend on where the estimate starts.
struct AlignedTrajectoryError {
  std::size_t matched = 0;     ///< estimated poses with a truth pose at their timestamp
  double aligned_rmse_xy_m = 0;  ///< position RMSE after the best rigid SE(2) alignment (Horn)
  /// Mean relative error over pose pairs `delta` metres of the truth's path apart (Kümmerle et
  /// al. 2009): |(est_i^-1 est_j) - (gt_i^-1 gt_j)| in translation [m] and heading [rad], for
  /// delta = 1 m and 10 m; NaN when the path is shorter.
  double rel_1m_xy_m = 0, rel_1m_phi_rad = 0;
  double rel_10m_xy_m = 0, rel_10m_phi_rad = 0;
};

/// Pairs poses by timestamp like trajectoryError(), then scores them as above. The alignment is
/// the closed-form least-squares rotation and translation of the estimate's positions onto the
/// truth's (Umeyama / Horn, without scale).
AlignedTrajectoryError alignedTrajectoryError(const std::vector<TimedPose>& estimate,
                                              const std::vector<TimedPose>& truth,
                                              double time_tolerance_s = 1e-3);

/// √(a·b) and 2ab/(a+b); NaN when either is NaN, 0 when both are 0.
double geometricMean(double a, double b);
double harmonicMean(double a, double b);

// --- people (CLEAR MOT) --------------------------------------------------------------------------

struct MotOptions {
  double gate_m = 0.75;     ///< a track farther than this from a person never matches it
  int min_visible_hits = 3;  ///< a person with fewer beams on them is not counted
  /// A person of the truth stops where they stay within stop_radius_m of where they stood
  /// still for at least stop_min_s (a turn at a path's end is no stop); a switch from their
  /// stop's first scan to after_stop_s after its last (walking off) is a switch at a stop.
  double stop_radius_m = 0.02;
  double stop_min_s = 2.0;
  double after_stop_s = 5.0;
};

/// A person of the truth matched to another track id than in the scan they were last matched.
struct IdSwitch {
  std::size_t scan_index = 0;
  double t = 0;  ///< simulated seconds
  int person = 0;
  int from_id = 0, to_id = 0;  ///< the track ids before and after
  bool at_stop = false;        ///< while the person stood still, or walking off (MotOptions)
};

/// CLEAR MOT (Bernardin & Stiefelhagen 2008) over the scans of the truth. Per scan a person
/// keeps last scan's track when it is still within the gate; the others are matched at minimum
/// total distance (Hungarian). A person seen by fewer than min_visible_hits beams is not
/// counted, and a track matched to one is no false positive either (it is where a person is).
struct MotScores {
  std::size_t ground_truth = 0;  ///< person-scans counted
  std::size_t matches = 0, misses = 0, false_positives = 0, id_switches = 0;
  std::size_t id_switches_at_stops = 0;  ///< of id_switches, those at a stop
  double mota = 0;    ///< 1 - (misses + false positives + id switches) / ground truth
  double motp_m = 0;  ///< mean distance of the matches
  std::size_t people = 0;  ///< persons of the truth seen at all
  std::size_t track_ids = 0;
  std::vector<IdSwitch> switches;  ///< each identity switch, in scan order
};
MotScores evaluateClearMot(const std::vector<TruthRow>& truth,
                           const std::vector<PersonTrackRow>& tracks, const MotOptions& options = {});

}  // namespace dynamap
