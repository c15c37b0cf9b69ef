#pragma once
// Cylinders added to a real log's scans (dynamap perturb --add-objects): where they stand in the
// free space a first mapping of the log found, when they move (jumps while the robot looks
// elsewhere, or glides in view), and each scan's beams shortened to the first cylinder they meet
// before their own return. The truth is what the simulator writes, so `dynamap eval` scores the
// object table on real scans.
//
// Pure functions over plain data: no I/O; one seed gives one plan. The mapping layers know
// nothing of this: the scans they read are edited before they see them.

#include <cstdint>
#include <string>
#include <vector>

#include "dynamap/sim/world.h"

namespace dynamap::sim {

/// What to add: `text` of parseAddObjectsSpec, e.g. "objects=4,moves=10,seed=2,glide=3".
struct AddObjectsSpec {
  int objects = 4;  ///< cylinders, diameters spread evenly over [min, max]
  int moves = 10;   ///< moves planned (some may be dropped, each with a reason)
  std::uint64_t seed = 1;
  double min_diameter = 0.2, max_diameter = 0.6;  ///< [m]
  double glide_s = 0;              ///< 0: jumps made unseen; > 0: glides of this length in view
  double wall_clearance_m = 0.15;  ///< from the cylinder's edge to anything S does not hold free
  double path_clearance_m = 0.5;   ///< from the cylinder's edge to every pose of the robot
  int seen_scans = 10;             ///< a move counts when its new place is seen in this many scans
  int seen_beams = 3;              ///< ... each with this many beams on the cylinder
  /// ... and, from the first scan that sees it so, in this many within eval's detection window
  /// (10 s or 50 scans, whichever is longer): a glance is no chance to find it (D needs 5 hits).
  int window_seen = 5;
  double range_noise_m = 0.01;  ///< sd of the noise on a shortened beam
  /// Beams on a cylinder farther than this [m] do not count as seeing it (the mapper's
  /// max_distance_insertion: it never uses them); not a SPEC key, the command sets it.
  double counted_range_m = 1e9;
};

/// Parses "key=value,key=value": objects, moves, seed, sizes (MIN-MAX in m), glide (s), wall (m),
/// path (m), seen (scans), beams, window (scans). Throws std::invalid_argument naming the key and
/// the value.
AddObjectsSpec parseAddObjectsSpec(const std::string& text);

/// One scan of the log, as the planner and the editor need it.
struct ScanGeometry {
  double t = 0;  ///< [s] since the log's first scan
  Vec2 robot;
  Vec2 sensor;
  double sensor_phi = 0;
  double first_angle = 0, step = 0;  ///< beam i points at sensor_phi + first_angle + i * step
  float max_range = 0;
  /// A beam without a return reads max_range here, or after limitBeamsWithoutReturn how far
  /// the map holds its path free.
  std::vector<float> ranges;
  std::vector<std::uint8_t> valid;  ///< the scan's own validity flags
};

/// Where a cylinder may stand, as S held it at time `t`: per cell of S, the distance from its
/// centre to the nearest cell S does not hold free (0 for such a cell) and to the nearest pose of
/// the robot, both capped.
struct FreeSpace {
  double t = 0;  ///< [s] since the log's first scan: S as of this time
  double x_min = 0, y_min = 0, resolution = 0.05;
  int size_x = 0, size_y = 0;
  std::vector<float> clearance, path_distance;
  /// Fills both fields from `free` (one flag per cell, row by row) and the robot's positions.
  void build(const std::vector<std::uint8_t>& free, const std::vector<Vec2>& robot, double cap);
  /// The cell's clearance minus half a cell (the obstacle's near edge); 0 off the grid.
  double clearanceAt(Vec2 p) const;
  double pathDistanceAt(Vec2 p) const;
  /// [m] How far from `from` along `angle` every cell is free, up to `max` (0 when `from` is
  /// not on a free cell).
  double freeRun(Vec2 from, double angle, double max) const;
};

struct AddedObject {
  int id = 0;
  double diameter = 0;
  Vec2 start;
};

/// One move: the simulator's moves.csv row (times in seconds since the log's first scan).
struct AddedMove {
  int id = 0, object_id = 0;
  double t_start = 0, t_end = 0;
  Vec2 from, to;
};

struct AddedPlan {
  std::vector<AddedObject> objects;
  std::vector<AddedMove> moves;      ///< by t_start; ids 1.. in that order
  std::vector<std::string> dropped;  ///< one line per move planned and dropped: why
};

/// When planAddedObjects wants S: the start of each move's time slot (the first 15 % of the log
/// has no move, the last 5 % neither), then the end of the log.
std::vector<double> addedSlotTimes(double t_last, const AddObjectsSpec& spec);

/// Plans the cylinders and their moves over `scans` (by time, t from 0). `free` holds S at each
/// time of addedSlotTimes: a move of slot k goes where S held free at the slot's start, a
/// cylinder starts where S holds free at the end (the log without it). Each move's new place is
/// seen in spec.seen_scans scans with spec.seen_beams beams before the object's next move; a jump
/// is seen neither at its old nor at its new place within a second of it; a glide is in view for at
/// least half of its scans; no return of the log's own falls inside the new place (clearOfTheLog)
/// from the move to 10 s after it is seen enough. A move no place or time satisfies is dropped with
/// its reason.
AddedPlan planAddedObjects(const std::vector<ScanGeometry>& scans,
                           const std::vector<FreeSpace>& free, const AddObjectsSpec& spec);

/// Where object `index` of the plan stands at time t (gliding at constant speed).
Vec2 addedPositionAt(const AddedPlan& plan, std::size_t index, double t);

/// Beams of `scan` that meet the disc before their own return, within `counted_range` [m].
int beamsOnDisc(const ScanGeometry& scan, Vec2 centre, double radius, double counted_range = 1e9);

/// Beams of `scan` whose own return (valid, short of max_range) ends inside the disc: something
/// of the log stands where the cylinder would (the planner takes only S's free space, so it is
/// something that moves: a person walking through).
int ownReturnsInDisc(const ScanGeometry& scan, Vec2 centre, double radius);
/// The index of the first of `scans` (by time) at or after t; scans.size() when none is.
std::size_t firstScanAt(const std::vector<ScanGeometry>& scans, double t);
/// No scan of `scans` (by time) in [t0, t1] has a return of its own inside the disc: no one of
/// the log walks through the place then. The planner asks it of each move's new place from the
/// move to 10 s after the place is seen enough (eval's window), so that no scored move puts a
/// cylinder where a person of the log stands.
bool clearOfTheLog(const std::vector<ScanGeometry>& scans, Vec2 centre, double radius, double t0,
                   double t1);

/// A beam without a return of its own (invalid, or at max_range) says nothing of what it
/// crossed: glass, a black surface or an open door the map holds unknown beyond may stand in
/// its way. Each such beam of `scan` becomes invalid with the range up to which `free` (the
/// unedited log's S) holds its path free: a cylinder farther along it is not seen through
/// what the laser did not return from. Call before planning (beamsOnDisc, ownReturnsInDisc and
/// applyAddedObjects then read the beam's range as its reach).
void limitBeamsWithoutReturn(ScanGeometry& scan, const FreeSpace& free);

/// Shortens every beam of `scan` that meets a cylinder (at scan.t) before its own return to the
/// nearest one, plus Gaussian noise of sd spec.range_noise_m drawn from `seed_stream` (one draw
/// per beam shortened); returns the beams each object got within spec.counted_range_m, in
/// plan.objects order.
std::vector<int> applyAddedObjects(const AddedPlan& plan, ScanGeometry& scan,
                                   const AddObjectsSpec& spec, std::uint64_t seed_stream);

/// The detection window of eval (evaluation.h's EvalOptions): 10 s or 50 scans.
constexpr double kWindowS = 10;
constexpr std::size_t kWindowScans = 50;

/// How often a place is seen after a move: in `total` scans with seen_beams beams before the
/// object's next move, `in_window` of them within the detection window from the first.
struct Sightings {
  int total = 0, in_window = 0;
  bool enough(const AddObjectsSpec& s) const {
    return total >= s.seen_scans && in_window >= s.window_seen;
  }
};
/// `beams(i)` gives the beams on the place in scan i.
template <typename Beams>
Sightings sightings(const std::vector<ScanGeometry>& scans, double t0, double t1, int seen_beams,
                    Beams beams);

/// Drops every move whose new place the edited scans (all cylinders in) do not show enough
/// (Sightings::enough) before the object's next move; repeats until none is dropped and
/// renumbers the moves. Each drop is added to plan.dropped.
void dropUnseenMoves(const std::vector<ScanGeometry>& scans, const AddObjectsSpec& spec,
                     AddedPlan& plan);

/// The seed of scan `index`'s range noise (applyAddedObjects): the same in every pass over the
/// edited scans, so that each pass edits them alike.
std::uint64_t addedNoiseStream(const AddObjectsSpec& spec, std::size_t index);

/// S of a map made from the edited scans, one by one (the command maps them with dynamap's own
/// mapper on the log's known poses).
class EditedMap {
 public:
  virtual ~EditedMap() = default;
  /// Whether S holds free every cell whose centre lies within `radius` of `centre`, after the
  /// scans inserted so far.
  virtual bool heldFree(Vec2 centre, double radius) const = 0;
  /// Maps scan `index` of the log as the plan edits it (`edited`).
  virtual void insert(std::size_t index, const ScanGeometry& edited) = 0;
};

/// Maps `scans` (by time), each edited by the plan, into `map`, and before the first scan at
/// or after each move's start asks whether S holds the move's new place (the cylinder's disc
/// itself, not the planner's `wall` margin around it) free, as the planner asked of the unedited
/// log's S: where another cylinder stood, unseen since it left (or in its shadow), S still holds
/// the place, and no mapper of changes can tell the new one from what was there. Such a move
/// is dropped (the object stays; plan.dropped says why) and the pass goes on with the plan so
/// changed: a drop edits only later scans. Renumbers the moves.
void dropMovesIntoHeldPlaces(const std::vector<ScanGeometry>& scans, const AddObjectsSpec& spec,
                             AddedPlan& plan, EditedMap& map);

/// Drops move `m` (index into plan.moves) with its reason: the object stays where it stood, so
/// its later moves start from there. The ids are left as they were (renumberMoves).
void dropMove(AddedPlan& plan, std::size_t m, const std::string& why);
/// Numbers plan.moves 1.. in their order.
void renumberMoves(AddedPlan& plan);

template <typename Beams>
Sightings sightings(const std::vector<ScanGeometry>& scans, double t0, double t1, int seen_beams,
                    Beams beams) {
  Sightings out;
  std::size_t first = scans.size();
  for (std::size_t s = 0; s < scans.size() && scans[s].t < t1; ++s) {
    if (scans[s].t < t0 || beams(s) < seen_beams) continue;
    if (first == scans.size()) first = s;
    ++out.total;
    if (scans[s].t <= scans[first].t + kWindowS || s < first + kWindowScans) ++out.in_window;
  }
  return out;
}

}  // namespace dynamap::sim
