#pragma once
// ObjectTracker: groups the dynamic map's object cells into objects, gives each an identity by
// its size (Wolf & Sukhatme) helped by position and time, and keeps the object table and its
// events.
//
// Per scan it reads only the D cells that crossed object_threshold in that scan
// (DynamicGridMap::changedObjectCells) and a bounded neighbourhood of them, plus one check per
// known object against the scan's beams: its cost does not grow with the size of the map.
//
// The core steps are free functions over plain data, each in a unit of its own so that it can
// be tested without a map: clustering.h (cells and clusters), shape.h (circle fit, size
// estimate), identity.h (identity choice), scan_view.h (visibility of a place in a scan).
// track.h holds a followed cluster and its state (tentative, confirmed, stale); object_table.h
// the rows and events this class keeps. A confirmed track holds no shape of its own: its
// object's row is the one copy, refreshed from the track's cells and hit points.

#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "dynamap/objects/clustering.h"
#include "dynamap/objects/identity.h"
#include "dynamap/objects/object_options.h"
#include "dynamap/objects/object_table.h"
#include "dynamap/objects/scan_view.h"
#include "dynamap/objects/shape.h"
#include "dynamap/objects/track.h"

namespace dynamap {

class DynamicGridMap;

class ObjectTracker {
 public:
  explicit ObjectTracker(const ObjectOptions& options = {});

  /// The per-scan step, after `map` has inserted the scan seen as `view` (may be empty: then
  /// places are never "in view", only cells decide). Reads only changedObjectCells() and its
  /// neighbourhood.
  void update(const DynamicGridMap& map, const ScanView& view, double t, std::size_t scan_index);

  /// Discs (x, y, r) where something that keeps moving is (people, from a layer above): a
  /// cluster centred in one is not confirmed as an object; once no disc holds it, only scans
  /// that see it occupied count towards confirming it (what the person's legs left in D, not
  /// yet seen empty, is no object). A cluster that began counting towards confirmation before
  /// any disc held it is not held back (Tentative::settling_before_people). Applies from the
  /// next update on.
  struct KeepOut {
    double x, y, r;
  };
  void setKeepOut(std::vector<KeepOut> discs) { keep_out_ = std::move(discs); }

  /// Continues an earlier session's table, before the first update: `rows` become objects 1..n
  /// (row k must have id k + 1). A row that table listed (present or absent) is absent here,
  /// vanished at `t`, until this session finds it: identity by size then gives a detection the
  /// id of the carried object it fits, nearest first. Other rows keep their state and are never
  /// chosen. Each row's history becomes its carried place alone, so that a row whose history
  /// grows was found this session. Throws std::logic_error after an update or with ids out of
  /// order.
  void carryOver(std::vector<TrackedObject> rows, double t);

  /// At a continued session's end: a carried id whose claim was withdrawn or retracted is as it
  /// came again; then the carried ids go to the objects present now that fit them
  /// best, all at once. During the session each id went to the first detection of its size, often
  /// a partial view (smaller) or an object of a size near it; now every present object's size has
  /// settled. One assignment (solveAssignment) over the present objects and the carried rows
  /// the prior listed: a pair costs its size difference over size_tolerance plus the distance
  /// from the carried place over match_distance_scale, and sizes further apart than
  /// size_tolerance or places farther than far_match_distance never pair; an object stays new
  /// only when no such pair is left for it (between sessions anything may have been carried
  /// anywhere: the distance tells two candidates apart, not a candidate from none). An object whose
  /// id changes gets a Relabeled event (from_id: the id it had); a new object's old row becomes
  /// Relabeled, a carried id no object keeps is absent at its carried place again. Nothing without
  /// carryOver.
  void settleCarried(double t, std::size_t scan_index);
  /// Object `id` is no object but part of a wall that appeared (a layer above says so): a
  /// carried row becomes again as it came (not found this session); any other becomes
  /// Retracted, with a Retracted event, and its id goes to no detection again. False (nothing
  /// done) when `id` is no object listed in the table.
  bool retire(int id, double t, std::size_t scan_index);

  /// Withdraws object `id`, which is absent (gone from its place) and was a person standing, a
  /// layer above found: state Withdrawn, a Withdrawn event; no identity ever goes to it again.
  /// False (nothing done) when `id` is no object or not absent.
  bool withdraw(int id, double t, std::size_t scan_index);

  const ObjectOptions& options() const { return options_; }
  /// Every object ever reported, by id (objects()[id - 1]); a present object's shape is its
  /// track's estimate as of the last update.
  const std::vector<TrackedObject>& objects() const { return objects_; }
  /// Every event so far, in order.
  const std::vector<EventRecord>& events() const { return events_; }
  /// Events of the last update (a suffix of events()).
  std::size_t eventsOfLastUpdate() const { return events_.size() - events_before_update_; }
  /// Object cells currently known (D above threshold), wall noise included.
  std::size_t objectCellCount() const { return cells_.size(); }

 private:
  // The steps of update(), in order.
  void foldChanges(const DynamicGridMap& map, std::vector<CellKey>& dirty);
  /// Regroups the usable object cells near `dirty` into clusters, hands each to a track
  /// (owner of most of its cells, else a track it continues, else a new one) and rebuilds
  /// every track that gained or lost cells.
  void recluster(const DynamicGridMap& map, const std::vector<CellKey>& dirty);
  void collectPoints(const DynamicGridMap& map, const ScanView& view);
  /// The whole outline of each track a beam of this scan ended on (measureOutline), when the
  /// scan shows it: into the track's outline sizes and outline_now_.
  void measureOutlines(const ScanView& view);
  /// Whether (x, y), up to rounding, may lie on a cell a track owns: false only when it surely
  /// does not (off the grid, or inside a cell no track owns, clear of its edges).
  bool onObjectCell(const DynamicGridMap& map, double x, double y) const;
  void dropLostTracks(double t, std::size_t scan_index);
  void checkStalePlaces(const ScanView& view, double t, std::size_t scan_index);
  /// Reported tracks under review whose size has settled for confirm_scans get their identity
  /// judged again (settle()).
  void reviewReports(const ScanView& view, double t, std::size_t scan_index);
  void confirmTentatives(const ScanView& view, double t, std::size_t scan_index);
  void checkDrift(double t, std::size_t scan_index);
  void updateLastSeen(const ScanView& view, double t);

  // Clustering.
  /// Every cluster of usable cells within the join distance of a dirty cell, sorted by first
  /// cell; the cells reached go into `visited`.
  std::vector<std::vector<CellXY>> clustersNear(const DynamicGridMap& map,
                                                const std::vector<CellKey>& dirty,
                                                std::unordered_set<CellKey>& visited);
  /// Track `key` keeps its cells no cluster took (`visited`) and that are still object cells,
  /// plus `gained`; its shape and hugs_wall follow.
  void rebuild(const DynamicGridMap& map, int key, const std::unordered_set<CellKey>& visited,
               const std::vector<CellKey>& gained);
  /// An object cell that is not wall noise (memoised for one recluster).
  bool usable(const DynamicGridMap& map, CellKey k);
  bool isWallNoise(const DynamicGridMap& map, CellXY c) const;
  bool nearNotFree(const DynamicGridMap& map, CellXY c, double distance) const;
  /// Whether support_threshold is on and the track has cells, but fewer than min_cells: the
  /// cells beside it may complete it.
  bool shortOfCells(const Track& tr) const;
  /// The D cells beside a shortOfCells() track (within join_distance of its cells, not object
  /// cells) above support_threshold, in S's free space and not wall noise; 0 for any other.
  int supportCells(const DynamicGridMap& map, const Track& tr) const;
  int ownerOfMost(const std::vector<CellXY>& cluster) const;
  /// The non-stale track whose shape a cluster of shape `s` continues, or 0.
  int followedTrack(const ShapeEstimate& s) const;
  /// [m] `object`'s radius + follow_margin: new cells this near its centre continue it.
  double reachOf(const ShapeEstimate& object) const;
  /// Re-measures the track; a confirmed track's estimate goes to its object's row.
  void refresh(Track& tr, double resolution);

  // Identity and state changes.
  /// The objects a detection of shape `s` may be, as chooseIdentity sees them, and their ids.
  void identityCandidates(const ShapeEstimate& s, int exclude_id, const ScanView& view, double t,
                          std::vector<IdentityCandidate>& cands, std::vector<int>& ids) const;
  /// The known object a detection of shape `s` is, or 0 for a new one. With `slack` > 0 [m]
  /// (report_errors times the error of s.size), -1 when a size `slack` above or below would
  /// change the choice.
  int pickIdentity(const ShapeEstimate& s, int exclude_id, double slack, const ScanView& view,
                   double t) const;
  /// Reports tentative track `key` under an identity (new, moved, reappeared): before
  /// confirm_scans a provisional one, from its outlines' size, kept under review. False when
  /// not reported yet: that size's error could change the identity, or (after confirm_scans)
  /// the only fit is an object at an out-of-sight place it waits for (defer_s).
  bool confirm(int key, const ScanView& view, double t, std::size_t scan_index);
  /// Track `key` becomes object `id` (0: a new one) with shape `s`; the event says how.
  void claim(int key, int id, const ShapeEstimate& s, std::optional<Review> review, double t,
             std::size_t scan_index);
  /// Judges the identity of reported track `key` again, as if it had not been reported; a
  /// different one replaces it (a relabeled event).
  void settle(int key, const ScanView& view, double t, std::size_t scan_index);
  /// Undoes what reporting track `key` under review did to the table: a new object is hidden
  /// (`hidden`), a known object gets its row back and its place if that was not seen empty.
  void undoClaim(int key, ObjectState hidden, double t, std::size_t scan_index);
  /// Whether this scan shows the whole outline of track `key` (shape `s`): a run of beams on
  /// it with an edge at each end (ObjectOptions::outline_jump), no larger than an object and
  /// holding its cells. Then `size` [m] is fitted to the run and `gap` [m] is the beams'
  /// spacing there.
  bool measureOutline(const ScanView& view, int key, const ShapeEstimate& s, double& size,
                      double& gap) const;
  /// Whether the place object `id` left for track `key`'s report is being seen occupied.
  bool leftPlaceSeenOccupied(int id, int key) const;
  /// Whether some track reports object `id` provisionally.
  bool underReview(int id) const;
  /// Object `id` was found elsewhere (by track `moved_to`): its track becomes a stale place.
  void leavePlace(int id, int moved_to);
  /// Stale `place` was seen occupied while track `took` still holds its object's id: `place` is
  /// its object again, and `took` gets the identity that fits it now (another known object,
  /// one seen gone since say, or a new one).
  void revive(Track& place, int took, const ScanView& view, double t, std::size_t scan_index);
  int newObject(double t);
  /// settleCarried's assignment: for each present object (by id) and each stale place still
  /// holding cells (by minus its track's key), the id it should hold (0: a new one).
  std::map<int, int> carriedAssignment() const;
  /// Whether object `id` (>= 1) came from carryOver, and its row as it came.
  bool isCarried(int id) const { return id <= static_cast<int>(carried_.size()); }
  const TrackedObject& carriedRow(int id) const {
    return carried_[static_cast<std::size_t>(id - 1)];
  }
  /// Object `to`'s row becomes present with `row`'s shape and times (settleCarried); `fresh`:
  /// a new row, which takes its first sighting from `row`.
  void giveId(int to, const TrackedObject& row, bool fresh);
  void emit(double t, std::size_t scan_index, const TrackedObject& o, ObjectEvent e);
  TrackedObject& object(int id) { return objects_[static_cast<std::size_t>(id - 1)]; }
  /// The key of the track confirmed as object `id`, or 0.
  int trackOf(int id) const;
  /// A track's shape: its own while tentative or stale, its object's row's once confirmed.
  const ShapeEstimate& shapeOf(const Track& tr) const;

  ObjectOptions options_;
  double resolution_ = 0;
  int origin_x_ = 0, origin_y_ = 0;               // global cell of the grid's cell (0, 0)
  double sensor_x_ = 0, sensor_y_ = 0;            // where the last scan was taken from
  std::unordered_set<CellKey> cells_;             // every D object cell
  std::unordered_map<CellKey, int> owner_;        // cell -> key of its track
  std::unordered_map<CellKey, bool> noise_memo_;  // cell -> wall noise, for one recluster
  std::map<int, Track> tracks_;                   // by key, in creation order
  int next_track_ = 1;
  std::set<int> touched_;               // tracks whose cells changed this scan
  std::set<int> pending_;               // tentatives passing the filters
  std::set<int> reviewing_;             // reported tracks whose identity is provisional
  std::map<int, std::size_t> beam_on_;  // track key -> a beam of this scan ending on its cells
  // track key -> the size and beam gap [m] of its whole outline in this scan
  std::map<int, std::pair<double, double>> outline_now_;
  const DynamicGridMap* map_ = nullptr;  // the map of the update under way
  std::vector<TrackedObject> objects_;
  std::vector<TrackedObject> carried_;  // the rows carryOver took, as they came
  std::vector<EventRecord> events_;
  std::size_t events_before_update_ = 0;
  std::vector<KeepOut> keep_out_;
  bool nearKeepOut(const ShapeEstimate& shape) const;
  /// Whether `shape` lies within a reported object's radius + follow_margin while this scan
  /// sees that object in place (a beam ends on its cells or its disc is seen occupied) or
  /// reports it: another arc of it (cells apart by more than join_distance on a far or
  /// sparsely seen object), never a second object.
  bool partOfASeenObject(const ShapeEstimate& shape, const ScanView& view) const;
  /// Whether an event of this update names object `id`.
  bool reportedThisScan(int id) const;
  /// What the scan shows of the disc a shape fills.
  PlaceView viewOfShape(const ScanView& view, const ShapeEstimate& s) const;
};

}  // namespace dynamap
