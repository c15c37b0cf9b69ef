#pragma once
// ObjectTracker: groups the dynamic map's object cells into objects, gives each an identity by
// its size (Wolf & Sukhatme) helped by position and time, and keeps the object table and its
// events.
//
// Per scan it reads only the D cells that crossed object_threshold in that scan
// (DynamicGridMap::changedObjectCells) and a bounded neighbourhood of them, plus one check per
// known object against the scan's beams: its cost does not grow with the size of the map.
//
// The core steps are free functions over plain data (clustering, circle fit, size estimate,
// identity choice, visibility of a place in a scan) so that they can be tested without a map.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <iosfwd>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace dynamap {

class IniFile;
class DynamicGridMap;

/// Options of the object tracker (section [objects]). Lengths in metres, counts in scans/cells.
struct ObjectOptions {
  static constexpr const char* kSection = "objects";

  bool enabled = true;  ///< track objects at all (false: no object outputs)
  double join_distance =
      0.15;  ///< [m] object cells this close (centre to centre) form one cluster; [0.01, 2]
  int min_cells = 2;       ///< fewer cells than this is not an object; [1, 1000]
  double min_size = 0.06;  ///< [m] smaller estimated sizes are noise; [0, max_size)
  double max_size = 1.2;  ///< [m] larger clusters are not objects (walls seen off by localisation);
                          ///< (min_size, 20]
  /// a new cluster is reported after passing the filters this many scans in a row with its
  /// size estimate settled (changing by at most settle_size from scan to scan): an object is
  /// judged once the robot has seen enough of it to tell its size. 10 scans (2 s at 5 Hz):
  /// 8 to 15 all meet the bundled scenarios' identity floors, 5 does not; [1, 1000]
  int confirm_scans = 10;
  double settle_size = 0.02;  ///< [m] see confirm_scans; [0, 1]
  /// [m] D cells this close to a cell S does not hold free (wall, unknown) are wall noise:
  /// grazing beams free the cells along walls, then hits there feed D; [0, 1]
  double wall_hug_distance = 0.1;
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
  double match_time_scale = 60.0;  ///< [s] among similar sizes, a vanishing this much older costs
                                   ///< as much as size_tolerance; > 0
  double match_distance_scale =
      10.0;               ///< [m] likewise for the distance from the object's last place; > 0
  int min_fit_cells = 6;  ///< a circle fit needs this many cells (or hit points), else the
                          ///< size is their width; [3, 1000]

  /// Strict load of [objects]: unknown keys, malformed or out-of-range values throw ConfigError.
  void load(const IniFile& ini);
  /// Throws ConfigError ("<source>: [objects] key: why") for the first rule broken.
  void validate(const std::string& source) const;
  /// Writes the section, one key per line with its meaning (reloadable).
  void writeIni(std::ostream& out) const;
};

// --- plain data ------------------------------------------------------------------------------

/// A grid cell in global integer coordinates (cell (0,0) holds the world origin), so that keys
/// stay valid when the map grows.
struct CellXY {
  int x, y;
};
using CellKey = std::int64_t;
inline CellKey cellKey(int x, int y) {
  // Shifted as unsigned: a negative x shifted left is undefined behaviour before C++20.
  return static_cast<CellKey>((static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) ^
                              static_cast<std::uint32_t>(y));
}
inline CellXY cellOf(CellKey k) {
  return {static_cast<int>(k >> 32), static_cast<int>(static_cast<std::uint32_t>(k & 0xffffffff))};
}

/// What a cluster of cells says about the object it belongs to.
struct ShapeEstimate {
  double cx = 0, cy = 0;                              ///< [m] centre
  double size = 0;                                    ///< [m] diameter
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;  ///< [m] the object's box
  bool circle = false;   ///< true: from a circle fit; false: from the cells' width
  double thickness = 0;  ///< [m] std of the cell centres across their main axis (0: a row)
  double length = 0;     ///< [m] widest distance between cell centres
  std::size_t cells = 0;
};

/// A circle through points: algebraic (Kasa) fit refined by a few Gauss-Newton steps on the
/// geometric distance. False when degenerate (fewer than 3 points, collinear points).
struct Circle {
  double cx, cy, r;
};
bool fitCircle(const std::vector<double>& xs, const std::vector<double>& ys, Circle& out);

/// The shape of the object seen as the centres of `cells` (global cells of `resolution` m).
/// A circle fit when there are enough cells and the fit is sane (radius at least half the
/// cells' width minus a cell, at most max_size/2, centre not among the cells); otherwise the
/// widest extent of the cells plus one cell, centred on their box. A cylinder seen from one
/// side shows an arc whose fit gives the whole cylinder; a half-seen object keeps its width.
ShapeEstimate estimateShape(const std::vector<CellXY>& cells, double resolution,
                            const ObjectOptions& options);

/// The shape of an object from the laser's own hit points on it (not the cells they fell in):
/// centimetre-precise where cells are 5 cm. A circle fit when the points show a sane arc (as wide
/// as the points at least, at most max_size, little residual, its centre beyond the points as
/// seen from (sensor_x, sensor_y)); otherwise the widest distance between points plus `gap`
/// (the beams' spacing there: each edge lies somewhere between the last beam that hit and the
/// first that missed), the visible outline of a convex object, centred on their box. False
/// with fewer than min_fit_cells points.
bool estimatePointShape(const std::vector<double>& xs, const std::vector<double>& ys, double gap,
                        double sensor_x, double sensor_y, const ObjectOptions& options,
                        ShapeEstimate& out);

/// Groups cells into clusters: two cells whose centres are within `join_cells` cells (Euclidean)
/// belong to the same cluster. Deterministic order (by the smallest key of each cluster).
std::vector<std::vector<CellXY>> clusterCells(const std::vector<CellXY>& cells, double join_cells);

/// What one scan tells about a round place.
enum class PlaceView { NotInView, SeenFree, SeenOccupied };

/// The beams of one scan in the map frame, enough to ask whether a place was seen.
struct ScanView {
  double x = 0, y = 0, phi = 0;  ///< sensor pose
  double first = 0, step = 0;    ///< beam i looks at phi + dir * (first + i * step)
  double dir = 1;
  double max_range = 0;
  std::vector<float> ranges;  ///< < 0: no echo
  bool empty() const { return ranges.empty(); }
};
/// The view of a scan taken from `robot` (sensor pose from the scan itself); `max_range` cuts.
ScanView makeScanView(const mrpt::obs::CObservation2DRangeScan& scan,
                      const mrpt::poses::CPose2D& robot, double max_range);
/// Whether the scan's beams crossed the disc (cx, cy, r) (SeenFree), ended in it
/// (SeenOccupied), or never reached it (NotInView: out of range, out of the field of view, or
/// hidden behind something nearer). `margin` [m] tolerates range noise and cell size.
PlaceView viewOf(const ScanView& view, double cx, double cy, double r, double margin);

/// A known object, as identity by size sees it.
struct IdentityCandidate {
  double cx, cy, size;
  bool absent;        ///< seen vacated (or never seen at its place again)
  double vanished_t;  ///< when it was marked absent (absent only)
  PlaceView view;     ///< what this scan shows of its known place (present only)
};
/// Which known object a newly confirmed detection is, or -1 for a new object. Candidates:
/// sizes within size_tolerance; absent objects first (the paper's rule), then present objects
/// whose place this scan shows free or does not show (an object moved while its old place was
/// out of sight); never an object seen at its place now. Among candidates of one kind, the
/// smallest cost |size difference| / size_tolerance + age / match_time_scale +
/// distance / match_distance_scale wins, so of two similar sizes the one that just vanished,
/// nearer, is chosen.
int chooseIdentity(const ShapeEstimate& detection, double t,
                   const std::vector<IdentityCandidate>& candidates, const ObjectOptions& options);

// --- the table ---------------------------------------------------------------------------------

enum class ObjectState { Present, Absent };
const char* toString(ObjectState s);

enum class ObjectEvent { New, Moved, Disappeared, Reappeared };
const char* toString(ObjectEvent e);

struct PositionRecord {
  double t, cx, cy;
};

/// One row of the object table.
struct TrackedObject {
  int id = 0;           ///< 1, 2, ... in order of first report
  std::string label;    ///< "object<id>"
  ShapeEstimate shape;  ///< last estimate (kept while absent)
  ObjectState state = ObjectState::Present;
  double first_seen_t = 0, last_seen_t = 0;
  int n_moves = 0;
  double vanished_t = 0;                ///< when it was last marked absent
  std::vector<PositionRecord> history;  ///< where it was found: at new, moved, reappeared
};

struct EventRecord {
  double t;
  std::size_t scan_index;
  int object_id;
  ObjectEvent event;
  double cx, cy, size;
};

class ObjectTracker {
 public:
  explicit ObjectTracker(const ObjectOptions& options = {});

  /// The per-scan step, after `map` has inserted the scan seen as `view` (may be empty: then
  /// places are never "in view", only cells decide). Reads only changedObjectCells() and its
  /// neighbourhood.
  void update(const DynamicGridMap& map, const ScanView& view, double t, std::size_t scan_index);

  const ObjectOptions& options() const { return options_; }
  /// Every object ever reported, by id.
  const std::vector<TrackedObject>& objects() const { return objects_; }
  /// Every event so far, in order.
  const std::vector<EventRecord>& events() const { return events_; }
  /// Events of the last update (a suffix of events()).
  std::size_t eventsOfLastUpdate() const { return events_.size() - events_before_update_; }
  /// Object cells currently known (D above threshold), wall noise included.
  std::size_t objectCellCount() const { return cells_.size(); }

 private:
  // A cluster being followed: confirmed ones carry an object id, tentative ones id 0. A stale
  // one holds the cells an object left when its move was not seen (stale_of = its id): it is
  // never reported, and ends when its cells fade (the place was seen free) or, seen occupied,
  // becomes a tentative cluster again (the object there was another one).
  struct Track {
    int id = 0;
    std::vector<CellKey> cells;
    ShapeEstimate shape;
    int passes = 0;                     // consecutive scans passing the filters (tentative)
    double last_size = 0;               // size at the last filter pass
    double first_t = 0;                 // when it first passed
    std::size_t best_cells = 0;         // most cells seen at this place: the size follows those
    double anchor_x = 0, anchor_y = 0;  // where the last event placed it
    int exclude_id = 0;  // identity must not pick this object (a stale place re-found)
    int stale_of = 0;
    int moved_to = 0;        // stale: the track whose detection took its id
    bool hugs_wall = false;  // some cell is near a cell S does not hold free
    // The latest hit point in each centimetre bin of its cells: the size is fitted to these.
    struct HitPoint {
      double x, y;
      double gap;    // [m] between its beam and the next at that range
      CellKey cell;  // the object cell it fell in
    };
    std::map<CellKey, HitPoint> points;
    int seen_occupied = 0;  // stale: consecutive scans that saw the place occupied
  };

  void foldChanges(const DynamicGridMap& map, std::vector<CellKey>& dirty);
  void recluster(const DynamicGridMap& map, const std::vector<CellKey>& dirty);
  std::vector<CellXY> usableNeighbours(const DynamicGridMap& map, CellKey seed, int radius) const;
  bool isWallNoise(const DynamicGridMap& map, CellXY c) const;
  bool nearNotFree(const DynamicGridMap& map, CellXY c, double distance) const;
  int ownerOfMost(const std::vector<CellXY>& cluster) const;
  int followedTrack(const ShapeEstimate& s) const;
  void refresh(Track& tr, double resolution);
  void collectPoints(const DynamicGridMap& map, const ScanView& view);
  bool passesFilters(const Track& tr) const;
  void dropLostTracks(double t, std::size_t scan_index);
  void confirmTentatives(const ScanView& view, double t, std::size_t scan_index);
  bool confirm(int key, const ScanView& view, double t, std::size_t scan_index);
  int newObject(double t);
  void checkDrift(double t, std::size_t scan_index);
  void checkStalePlaces(const ScanView& view, double t, std::size_t scan_index);
  void updateLastSeen(const ScanView& view, double t);
  void emit(double t, std::size_t scan_index, const TrackedObject& o, ObjectEvent e);
  TrackedObject& object(int id) { return objects_[static_cast<std::size_t>(id - 1)]; }
  int trackOf(int id) const;

  ObjectOptions options_;
  double resolution_ = 0;
  int origin_x_ = 0, origin_y_ = 0;         // global cell of the grid's cell (0, 0)
  double sensor_x_ = 0, sensor_y_ = 0;      // where the last scan was taken from
  std::unordered_set<CellKey> cells_;       // every D object cell
  std::unordered_map<CellKey, int> owner_;  // cell -> key of its track
  std::map<int, Track> tracks_;             // by key, in creation order
  int next_track_ = 1;
  std::set<int> touched_;  // tracks whose cells changed this scan
  std::set<int> pending_;  // tentatives passing the filters
  std::vector<TrackedObject> objects_;
  std::vector<EventRecord> events_;
  std::size_t events_before_update_ = 0;
};

}  // namespace dynamap
