#pragma once
// What changed since the last session (`dynamap map --prior`): the change report of one session
// mapped from an earlier one's state (session_state.h).
//
// The session starts from the prior's S and its object table (every object absent until found
// again, ObjectTracker::carryOver); D starts empty, so that what D holds is what moved in this
// session. Per scan SessionChanges notes, for each object the prior table held present, whether
// the scan saw its place empty or occupied, and when each D cell crossed object_threshold. Its
// cost per scan is one check per carried object and one step per D cell that crossed: it does
// not grow with the map. report() reads the maps once, at the end:
//
//  * object_moved: a carried object found this session farther than [objects] move_distance
//    from its place in the prior (which, if the prior held it present, gone_views scans saw
//    empty, more than saw it occupied); or an object new to the table whose size (within [objects]
//    size_tolerance) is that of a place the prior's S held occupied and S now holds free (an
//    object that had never moved before: the paper's S holds it), or holds no longer surely
//    occupied beside space the prior never saw and this session sees free (seen through: a
//    place glimpsed, not yet free; never alone reported gone), at most [objects]
//    far_match_distance away. object_new: an object new to
//    the table, present at the session's end, that came from no such place. object_gone: a
//    carried object present in the prior, not found this session, whose place at least
//    gone_views scans saw empty, more than saw it occupied; or such a place (of at least
//    structure_min_cells cells) no new object came from: an object of the prior's S, no id (0).
//  * structure_added: cells the prior's S held free that D holds at the end, each for at least
//    structure_stay_s, grouped (8-neighbours) into regions wider than [objects] max_size (a
//    narrower one is an object, the table's business) of at least structure_min_cells cells.
//  * structure_removed: cells the prior's S held occupied (above removed_occupancy) that S now
//    holds free, likewise
//    grouped into regions wider than [objects] max_size of at least structure_min_cells cells.
//  Cells within structure_margin of the other session's walls (the prior's occupied cells for an
//  addition, S's occupied cells now for a removal) are left out: there a wall seen a cell off, by
//  the two sessions' pose error, is no change.

#include <limits>
#include <ostream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dynamap/base/cell_key.h"
#include "dynamap/base/option_table.h"
#include "dynamap/input/session_state.h"
#include "dynamap/mapping/dynamic_grid_map.h"
#include "dynamap/objects/object_tracker.h"
#include "dynamap/objects/scan_view.h"

namespace dynamap {

/// [changes]: how a session's change report tells a change from noise.
struct ChangeOptions {
  static constexpr const char* kSection = "changes";
  /// [m] a structure change this close to the other session's walls is their pose error; [0, 2]
  double structure_margin = 0.15;
  int structure_min_cells =
      6;  ///< fewer cells are no change of S (structure, a place left); [1, 1e6]
  /// [s] "stays": an added structure's cells must have been in D this long at the session's
  /// end (what came and went again, or came at the very end, is no new structure); [0, 1e6]
  double structure_stay_s = 10.0;
  /// P(occ): only cells the prior's S held occupied at least this surely can be structure
  /// removed or a place an object left. 0.9 is three hits at s_hit_notfree 0.7: a person who
  /// stood a moment, a grazing beam, leave less. In [0.5, 1]
  double removed_occupancy = 0.9;
  int gone_views =
      5;  ///< scans that saw a carried object's place empty before it is gone; [1, 1e6]

  static const OptionTable<ChangeOptions>& table();
  void load(const IniFile& ini);
  void writeIni(std::ostream& out) const;
};

/// One row of changes.csv. `id`: the object's id, or the structure change's number (1, 2, ...
/// per kind). A place not known is NaN (no `from` for a new object, no `to` for a gone one).
struct ChangeRow {
  std::string kind;  ///< object_moved, object_new, object_gone, structure_added, structure_removed
  int id = 0;
  double size = 0;  ///< [m] an object's size; a structure change's longest extent
  double from_x = std::numeric_limits<double>::quiet_NaN(), from_y = from_x;
  double to_x = from_x, to_y = from_x;
  double first_seen_t = from_x;  ///< [s] when this session first saw it (NaN: not known)
  std::size_t cells = 0;         ///< a structure change's cells
  /// A structure change's cells (x, y) in the map's grid at report() (for pictures).
  std::vector<std::pair<int, int>> region;
};

class SessionChanges {
 public:
  /// `prior` is the earlier session's state; its grid must have `map`'s resolution.
  SessionChanges(SessionState prior, const ChangeOptions& options, const ObjectOptions& objects);

  /// After the scan seen as `view` was inserted into `map` at time `t`.
  void update(const DynamicGridMap& map, const ScanView& view, double t);

  /// What the grids say at the end, read once: structure added and removed (largest first),
  /// and the places objects of the prior's S left.
  struct GridChanges {
    std::vector<ChangeRow> structure, vacated;
  };
  GridChanges gridChanges(const DynamicGridMap& map) const;
  /// The changes, objects (by id) first, then added and removed structure (largest first).
  std::vector<ChangeRow> report(const DynamicGridMap& map, const ObjectTracker& tracker) const;
  /// The same from the grids' changes read before (`grid`, of the map as it still is).
  std::vector<ChangeRow> report(const GridChanges& grid, const ObjectTracker& tracker) const;
  /// The prior's S (raw MRPT value) at the cell holding (x, y); 0 (unknown) off its grid.
  std::int8_t priorCell(double x, double y) const;
  /// priorCell at the centre of every cell of `map`, row by row (index x + y * size_x): a grid
  /// grown from the prior's lies on it at whole cells, and is copied row by row.
  std::vector<std::int8_t> priorOnGrid(const DynamicGridMap& map) const;

 private:
  struct Place {
    int id;
    double cx, cy, size;
    int seen_free = 0, seen_occupied = 0;
  };
  /// Whether at least gone_views scans saw the place empty, more than saw it occupied.
  bool seenEmpty(const Place& p) const;
  /// Whether (x, y) lies within an object the prior's table listed (present or absent).
  bool onTablePlace(double x, double y) const;
  /// Changes of the objects the prior's table held.
  void carriedChanges(const ObjectTracker& tracker, std::vector<ChangeRow>& rows) const;
  /// carriedChanges, then each object new to the table: moved from the `vacated` place of its
  /// size (nearest first), else new; the places left over are objects gone.
  void objectChanges(const ObjectTracker& tracker, std::vector<ChangeRow> vacated,
                     std::vector<ChangeRow>& rows) const;
  /// Structure added and removed; a removed region of an object's size is no structure but a
  /// place an object of the prior's S left: into `vacated`.
  void structureChanges(const DynamicGridMap& map, std::vector<ChangeRow>& rows,
                        std::vector<ChangeRow>& vacated) const;
  /// Places of an object's size the prior's S held surely occupied, no longer sure now (not
  /// yet free), beside space the prior never saw and this session sees free: seen through,
  /// so no longer standing there. Into `vacated` (kind vacated_seen_through), outside the
  /// cells `taken` by the removed regions already found; `prior` is priorOnGrid(map).
  void seenThrough(const DynamicGridMap& map, const std::vector<std::int8_t>& prior,
                   const std::vector<std::uint8_t>& taken, std::vector<ChangeRow>& vacated) const;

  ChangeOptions options_;
  ObjectOptions objects_;
  SessionState prior_;
  std::vector<Place> places_;                    // the prior's present objects
  std::unordered_map<CellKey, double> entered_;  // D object cell (global) -> when it entered D
  double last_t_ = 0;
};

}  // namespace dynamap
