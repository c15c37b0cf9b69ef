#pragma once
// A submap: an occupancy grid of a few consecutive scans in the frame of its first scan (its
// anchor node in the pose graph), and the likelihood field scans are matched against.
//
// The grid is dynamap's own DynamicGridMap: its static map S holds what stood still while the
// submap was built, people and moved objects go to D, so only S is matched against (ScanMatcher
// for the front end, the likelihood field of S for loop closures). A finished submap keeps only
// its field (two bytes per cell of its occupied bounding box).

#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <memory>

#include "dynamap/localization/likelihood_field.h"
#include "dynamap/mapping/dynamic_grid_map.h"

namespace dynamap {

class Submap {
 public:
  /// `anchor`: the node whose pose is the submap's frame; the grid's options are the run's.
  Submap(std::size_t anchor, const DynamicMapOptions& map, const InsertionOptions& insertion);

  /// Inserts a scan taken from `local_pose` (the robot's pose in the submap's frame).
  void insert(const RangeData& rd, const mrpt::poses::CPose2D& local_pose);
  /// Builds the field from S and frees the grid: no scan can be inserted afterwards.
  void finish(double occupied_threshold, double sigma_m);
  /// The grid; nullptr once finished.
  const DynamicGridMap* map() const { return grid_.get(); }

  std::size_t anchor() const { return anchor_; }
  std::size_t scans() const { return scans_; }
  /// The last node inserted.
  std::size_t lastNode() const { return last_node_; }
  void setLastNode(std::size_t n) { last_node_ = n; }
  bool finished() const { return grid_ == nullptr; }
  const LikelihoodField& field() const { return field_; }

 private:
  std::size_t anchor_, last_node_;
  std::size_t scans_ = 0;
  std::unique_ptr<DynamicGridMap> grid_;
  LikelihoodField field_;
};

}  // namespace dynamap
