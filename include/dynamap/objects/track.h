#pragma once
// Track: a cluster of object cells the tracker follows from scan to scan, and the state it is
// in. The state is a variant holding the data of that state only, so a track cannot be, say,
// confirmed and stale at once, or stale without the object whose place it is.
//
//   Tentative --report--> Confirmed (under review) --size settled--> Confirmed
//   Confirmed --its object found elsewhere, move unseen--> Stale
//   Stale --seen occupied, its object's detection still under its id--> Confirmed (revived)
//   Stale --seen occupied, its object has moved on since--> Tentative (never that object)
// A track whose cells all faded ends: a confirmed one's object is then absent (retracted if it
// was still under review).

#include <cstddef>
#include <map>
#include <optional>
#include <variant>
#include <vector>

#include "dynamap/objects/clustering.h"
#include "dynamap/objects/object_options.h"
#include "dynamap/objects/object_table.h"
#include "dynamap/objects/shape.h"

namespace dynamap {

/// Consecutive scans passing the filters with a settled size: each changed by at most
/// settle_size since the scan before.
struct SettledRun {
  int passes = 0;
  double last_size = 0;  ///< [m] size at the last filter pass
  /// One more scan passing the filters, with size `size` [m]: the run grows if the size
  /// settled, else starts again at 1.
  void pass(double size, double settle_size);
};

/// Sizes fitted to the whole outline of an object, one per scan that showed it whole.
struct OutlineSizes {
  int count = 0;
  /// Sums of weight w, w·size, w·size² over them; a size weighs 1 / (beam spacing)²: the
  /// nearer the robot, the finer the outline.
  double w = 0, ws = 0, wss = 0;
  double gap = 0;  ///< [m] the smallest beam spacing among them
  /// Add one outline of `size` [m] seen with beams `gap` [m] apart.
  void add(double size, double gap);
  /// Their weighted mean (count > 0), and its uncertainty: max(spread, half the finest beam
  /// spacing) / sqrt(count).
  double size() const { return ws / w; }
  double error() const;
};

/// Not reported yet. It is reported, provisionally, once report_scans scans of its run of
/// filter passes have shown its whole outline and the identity that outline's size gives holds
/// for any size within its error; or, finally, after confirm_scans settled passes.
struct Tentative {
  ShapeEstimate shape;  ///< the cluster's shape
  SettledRun run;
  double first_t = 0;  ///< [s] when the current run of passes began
  int exclude_id = 0;  ///< identity must not pick this object (0: none): a stale place re-found
  /// A person stood on it (KeepOut): from then on only scans that see it occupied count, so
  /// the cells their legs left, not yet seen empty, are never an object.
  bool kept_out = false;
  /// It began counting passes before any person's keep-out covered it: something settling
  /// there before anyone came near. A person who then walks up to it or passes by does not hold
  /// it back (it is not their legs); a track a keep-out covered first never is so.
  bool settling_before_people = false;
  /// The sizes fitted to its whole outline, in the scans of this run that showed it whole
  /// (ObjectOptions::outline_jump): a first size before its cells have all crossed D.
  OutlineSizes outline;
  /// A run of passes broken: counting starts again.
  void restart() {
    run.passes = 0;
    outline = {};
  }
};

/// A report whose identity is provisional: given from the first size, judged again once the
/// size has settled for confirm_scans scans.
struct Review {
  SettledRun run;        ///< continues the tentative's
  double first_t = 0;    ///< [s] when the run of passes that reported it began
  int exclude_id = 0;    ///< as Tentative's
  bool claimed = false;  ///< the identity was a known object's...
  TrackedObject before;  ///< ...whose row, before this report, this is
};

/// Reported: it is object `id` of the table. Its shape is that object's row's
/// (TrackedObject::shape): the one copy, refreshed from its cells and hit points.
struct Confirmed {
  int id = 0;
  double anchor_x = 0, anchor_y = 0;  ///< [m] where the last event placed it
  std::size_t best_cells = 0;         ///< most cells seen at this place: the size follows those
  std::optional<Review> review;       ///< set while its identity is provisional
};

/// The cells object `object_id` left when its move was not seen: never reported. It ends when
/// its cells fade (the place was seen free), or is seen occupied and becomes tracked again.
struct Stale {
  int object_id = 0;
  ShapeEstimate shape;         ///< the place's shape (the object's row holds where it went)
  int moved_to = 0;            ///< key of the track whose detection took the object's id
  std::size_t best_cells = 0;  ///< as Confirmed's, kept should the place be revived
  int seen_occupied = 0;       ///< consecutive scans that saw the place occupied
};

using TrackState = std::variant<Tentative, Confirmed, Stale>;

/// The latest hit point in one centimetre bin of a track's cells.
struct HitPoint {
  double x, y;   ///< [m]
  double gap;    ///< [m] between its beam and the next at that range
  CellKey cell;  ///< the object cell it fell in
};

struct Track {
  std::vector<CellKey> cells;  ///< sorted
  bool hugs_wall = false;      ///< some cell is near a cell S does not hold free
  /// Every whole outline of it seen so far, in any state: once there is one, its size. A
  /// convex object's outline is as wide as the object from any side, while its cells and hit
  /// points show only the arcs that have crossed D so far (scans seconds apart, a place
  /// passed by): their size falls short.
  OutlineSizes outline;
  /// The latest hit point in each centimetre bin of its cells: the size is fitted to these.
  std::map<CellKey, HitPoint> points;
  TrackState state;  ///< a new track is tentative

  Tentative* tentative() { return std::get_if<Tentative>(&state); }
  Confirmed* confirmed() { return std::get_if<Confirmed>(&state); }
  Stale* stale() { return std::get_if<Stale>(&state); }
  const Confirmed* confirmed() const { return std::get_if<Confirmed>(&state); }
  const Stale* stale() const { return std::get_if<Stale>(&state); }
  bool isStale() const { return std::holds_alternative<Stale>(state); }
  /// The shape a tentative or stale track holds; null when confirmed (its object's row holds
  /// it).
  ShapeEstimate* ownShape();
  const ShapeEstimate* ownShape() const;
  /// The object this track is reported as, 0 when tentative or stale.
  int objectId() const { return confirmed() ? confirmed()->id : 0; }
};

/// The shape of the track's cells now (cells of `resolution` m), or, when its hit points allow,
/// the finer shape fitted to them (estimatePointShape seen from (sensor_x, sensor_y)) with the
/// cell count, thickness and length of the cells. Drops the hit points whose cell has left the
/// track, and every one of them when the cells are longer than max_size (a wall: no finer size
/// needed). At most 200 points, evenly through the bins, are fitted.
ShapeEstimate measureShape(Track& track, double resolution, double sensor_x, double sensor_y,
                           const ObjectOptions& options);

/// Raises a size `s` that is not a fitted circle to the mean of the whole outlines seen
/// (`outline`, when it holds one and that is larger), its box that size about its centre.
void applyOutline(const OutlineSizes& outline, ShapeEstimate& s);

/// Whether a tentative track of shape `shape` counts as a pass towards confirmation: enough
/// cells, a size within [min_size, max_size], and not a thin row of cells along a wall.
/// `support`: cells beside it that count towards min_cells (ObjectOptions::support_threshold).
bool passesFilters(const Track& track, const ShapeEstimate& shape, const ObjectOptions& options,
                   int support = 0);

}  // namespace dynamap
