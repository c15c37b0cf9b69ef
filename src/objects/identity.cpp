#include "dynamap/objects/identity.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynamap {

int chooseIdentity(const ShapeEstimate& det, double t,
                   const std::vector<IdentityCandidate>& candidates, const ObjectOptions& o) {
  // Present objects not seen at their place are a weaker explanation than absent ones: they
  // pay half a size tolerance.
  constexpr double kUnseenPenalty = 0.5;
  int best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const IdentityCandidate& c = candidates[i];
    const double ds = std::abs(c.size - det.size);
    if (ds > o.size_tolerance) continue;
    if (!c.absent && c.view == PlaceView::SeenOccupied) continue;
    const double age = c.absent ? std::max(0.0, t - c.vanished_t) : 0.0;
    const double dist = std::hypot(c.cx - det.cx, c.cy - det.cy);
    if (dist > o.far_match_distance && c.shared_size) continue;
    const double cost = ds / o.size_tolerance + age / o.match_time_scale +
                        dist / o.match_distance_scale + (c.absent ? 0.0 : kUnseenPenalty);
    if (cost < best_cost) {
      best_cost = cost;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace dynamap
