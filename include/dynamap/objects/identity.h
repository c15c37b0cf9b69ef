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

}  // namespace dynamap
