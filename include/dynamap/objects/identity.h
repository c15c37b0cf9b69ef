#pragma once
// Identity by size (Wolf & Sukhatme), helped by position and time: which known object a newly
// confirmed detection is.

#include <vector>

#include "dynamap/objects/object_options.h"
#include "dynamap/objects/scan_view.h"
#include "dynamap/objects/shape.h"

namespace dynamap {

/// A known object, as identity by size sees it.
struct IdentityCandidate {
  double cx, cy, size;
  bool absent;        ///< seen vacated (or never seen at its place again)
  double vanished_t;  ///< when it was marked absent (absent only)
  PlaceView view;     ///< what this scan shows of its known place (present only)
  /// another known object's size is as near the detection's, give or take far_size_margin
  bool shared_size = false;
};
/// Which known object a newly confirmed detection is, or -1 for a new object. Candidates:
/// sizes within size_tolerance; absent objects first (the paper's rule), then present objects
/// whose place this scan shows free or does not show (an object moved while its old place was
/// out of sight); never an object seen at its place now. Among candidates of one kind, the
/// smallest cost |size difference| / size_tolerance + age / match_time_scale +
/// distance / match_distance_scale wins, so of two similar sizes the one that just vanished,
/// nearer, is chosen. A candidate farther than far_match_distance is taken only when its size
/// is not shared (no other known object's size is as near the detection's): across a building,
/// a common size says nothing of which object it is.
int chooseIdentity(const ShapeEstimate& detection, double t,
                   const std::vector<IdentityCandidate>& candidates, const ObjectOptions& options);

}  // namespace dynamap
