#pragma once
// The truth and the tracks grouped by scan, and the walk over a move's detection window: shared
// by the scoring (evaluation.cpp) and the miss causes (miss_causes.cpp). Private to the
// evaluation layer.

#include <cstddef>
#include <map>
#include <vector>

#include "dynamap/evaluation/evaluation.h"

namespace dynamap {

/// The truth and the tracks, grouped by scan.
struct ByScan {
  std::map<std::size_t, std::vector<const TruthRow*>> bodies;
  std::map<std::size_t, double> t;  // the truth's time of each scan
  std::map<std::size_t, std::vector<const TrackRow*>> tracks;
};

/// Throws std::invalid_argument when a track row names a scan after the truth's last.
ByScan groupByScan(const std::vector<TruthRow>& rows, const std::vector<TrackRow>& tracks);

/// The rows of `by_scan` at `scan` (none when it has no entry there).
template <typename Row>
const std::vector<const Row*>& rowsAt(const std::map<std::size_t, std::vector<const Row*>>& by_scan,
                                      std::size_t scan) {
  static const std::vector<const Row*> kNone;
  const auto it = by_scan.find(scan);
  return it == by_scan.end() ? kNone : it->second;
}

/// The body `key` among `bodies`, or nullptr.
const TruthRow* findBody(const std::vector<const TruthRow*>& bodies, BodyKey key);

/// Calls f(scan, t, body, bodies) for every scan of the visible move `r`'s detection window (of
/// move `m`) at which its object stands at its new place, in scan order: `body` is the object's
/// row there, `bodies` every row of that scan.
template <typename F>
void forEachWindowScan(const ByScan& g, const TruthMove& m, const MoveResult& r,
                       const EvalOptions& options, F&& f) {
  const BodyKey object{sim::BodyKind::Object, m.object_id};
  for (auto it = g.bodies.find(r.visible_scan); it != g.bodies.end(); ++it) {
    const double t = g.t.at(it->first);
    if (!inDetectWindow(r, it->first, t, options)) break;
    const TruthRow* b = findBody(it->second, object);
    if (!b || sim::distance({b->x, b->y}, m.to) > options.place_tolerance_m) continue;
    f(it->first, t, *b, it->second);
  }
}

}  // namespace dynamap
