#pragma once
// Person detections from one scan: the scan's hit points that fall where the static map S holds
// free space (Wolf & Sukhatme's condition for "something moved in"), cut into clusters of
// neighbouring beams; leg-sized clusters close together are paired into one person. A wall is
// never Free in S, so its points never make a detection.
//
// The steps are free functions over plain data so that each can be tested without a map.

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <vector>

#include "dynamap/base/range_data.h"
#include "dynamap/people/people_options.h"

namespace dynamap {

class DynamicGridMap;
class LegClassifier;

/// One beam's end point in the map frame.
struct HitPoint2 {
  double x = 0, y = 0;
  std::size_t beam = 0;
};

/// The sensor's position and the hit points of one scan (beams with an echo within max_range).
struct ScanHits {
  double sensor_x = 0, sensor_y = 0;
  std::vector<HitPoint2> points;  ///< in beam order
  /// Per beam: the range [m] of its echo, or < 0 without one (for "is this place seen empty").
  std::vector<float> ranges;
  std::vector<double> angles;  ///< per beam: its direction in the map frame [rad]
  /// cos and sin of `angles` (filled by scanHits; empty: viewDisc works them out itself)
  std::vector<double> cosines, sines;
  double max_range = 0;  ///< [m] a beam without an echo saw free space this far
  double step = 0;       ///< [rad] between neighbouring beams
};
/// The hits of a scan whose geometry is `rd`, taken with the robot at `robot`: its Hit beams
/// (an echo below rd.insertion_range); an echo at or past it is free space that far.
ScanHits scanHits(const RangeData& rd, const mrpt::poses::CPose2D& robot);
/// The same into `out`, reusing its buffers (the per-scan step allocates nothing once warm).
void scanHits(const RangeData& rd, const mrpt::poses::CPose2D& robot, ScanHits& out);
/// The same for a scan whose RangeData the caller has not made (tests, tools).
ScanHits scanHits(const mrpt::obs::CObservation2DRangeScan& scan, const mrpt::poses::CPose2D& robot,
                  double max_range);

/// The points of `hits` whose cell, and every cell within wall_guard_cells of it, S holds free.
std::vector<HitPoint2> freeSpaceHits(const DynamicGridMap& map, const ScanHits& hits,
                                     int wall_guard_cells);

/// A run of hit points of neighbouring beams (at most one beam skipped), each within
/// cluster_distance of the one before, or within twice the beams' spacing at its range
/// (`beam_step` rad): far away, one body's points lie wider apart than near.
struct PointCluster {
  double cx = 0, cy = 0;  ///< [m] centre of the round body the points lie on (see clusterCentre)
  /// [m] widest distance between two of its points (and half a beam gap past each end); over
  /// max_person_width, only known to be over it (such a cluster is no person)
  double width = 0;
  std::size_t points = 0;
};
/// Splits `points` (in beam order) into clusters; clusters of fewer than min_points are dropped.
std::vector<PointCluster> clusterPoints(const std::vector<HitPoint2>& points, double sensor_x,
                                        double sensor_y, const PeopleOptions& options,
                                        double beam_step = 0);

/// A person seen in this scan.
struct PersonDetection {
  double x = 0, y = 0;
  int legs = 0;  ///< 2: a pair of legs; 1: one leg; 0: one body-sized cluster
  /// An object cell of D, or a cell of a body S holds that fits in object_max_extent (not a
  /// wall), lies within static_clearance of it (set by detectPeople): it may be an object
  /// leaving the place it stood at.
  bool near_static = false;
  /// This scan's beams pass through cells S holds occupied within static_clearance of it and
  /// end well beyond them (set by detectPeople): something that stood there has just left, and
  /// this may be it, moving off. Unlike near_static it tells an object that stood against a
  /// wall (one body with the wall in S) from the wall, which is never seen through. Left false
  /// when near_static, which holds a track to confirm_static_s already.
  bool static_left = false;
  /// Found by the leg classifier alone (no hit of it in S's free space): its legs' shape.
  bool shape = false;
  /// The classifier sees a pair of legs here (this detection, or one of shapeDetections within
  /// leg_pair_distance / 2 of it): a person by their shape, whether or not they move.
  bool leg_shaped = false;
};
/// Legs (clusters up to max_leg_width) are paired greedily, nearest pair first, when their
/// centres are within leg_pair_distance: the person is at the pair's midpoint. An unpaired leg
/// and a cluster up to max_person_width are a person on their own; wider clusters are dropped.
std::vector<PersonDetection> pairLegs(const std::vector<PointCluster>& clusters,
                                      const PeopleOptions& options);

/// The clusters of `hits` that `legs` takes for legs (leg_probability) and S does not hold
/// occupied (most of their points on cells S holds occupied: a wall, a chair S knows), paired
/// as pairLegs pairs them, each marked `shape`.
std::vector<PersonDetection> shapeDetections(const DynamicGridMap& map, const ScanHits& hits,
                                             const PeopleOptions& options, const LegClassifier& legs);

/// n as a share of `hits`' points (0 for a scan without hits).
double shareOfHits(std::size_t n, const ScanHits& hits);
/// The share of `hits` that lie on surfaces wider than `length` among `free` (freeSpaceHits of
/// them; clusterPoints): walls seen from the wrong place, where the poses are off; no object or
/// person is that wide.
double freeSurfaceShare(const std::vector<HitPoint2>& free, const ScanHits& hits,
                        const PeopleOptions& o, double length);

/// The whole detection step: freeSpaceHits, clusterPoints, pairLegs, and near_static; with
/// `legs`, also the shapeDetections farther than leg_pair_distance / 2 from every one of those
/// (a pair of legs among the nearer ones makes the detection they are near leg_shaped).
/// `free_hits`, when given, receives the scan's hits in S's free space (freeSpaceHits): a few
/// percent of them where the map holds still, most where the poses are wrong (drift, or a
/// moving robot mapped with fixed poses).
std::vector<PersonDetection> detectPeople(const DynamicGridMap& map, const ScanHits& hits,
                                          const PeopleOptions& options,
                                          const LegClassifier* legs = nullptr,
                                          std::vector<HitPoint2>* free_hits = nullptr);

}  // namespace dynamap
