// planAddedObjects: where the added cylinders stand and when they move (added_objects.h).

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "dynamap/sim/added_objects.h"
#include "dynamap/sim/random.h"

namespace dynamap::sim {

namespace {

constexpr double kObjectGap = 0.4;   // between two cylinders' edges [m], as the simulated worlds
constexpr double kJumpUnseen = 1.0;  // no beam on either place this long around a jump [s]
constexpr double kGlideMin = 0.5, kGlideMax = 2.0;  // a glide's length [m]
constexpr int kTimeTries = 30, kPlaceTries = 60, kStartTries = 3000;

class Planner {
 public:
  Planner(const std::vector<ScanGeometry>& scans, const std::vector<FreeSpace>& free,
          const AddObjectsSpec& spec)
      : scans_(scans), all_free_(free), spec_(spec), rng_(spec.seed) {}

  AddedPlan plan() {
    if (scans_.empty()) throw std::invalid_argument("no scans to add objects to");
    const std::vector<double> times = addedSlotTimes(scans_.back().t, spec_);
    if (all_free_.size() != times.size()) {
      throw std::invalid_argument("planAddedObjects: one free space per slot time expected");
    }
    const double begin = times.front(), slot = times.size() > 2 ? times[1] - times[0]
                                                                 : times.back() - times.front();
    useFreeSpace(all_free_.back());
    placeObjects(begin);
    free_after_.assign(plan_.objects.size(), 0);
    last_move_.assign(plan_.objects.size(), -1);
    for (int k = 0; k < spec_.moves; ++k) {
      useFreeSpace(all_free_[static_cast<std::size_t>(k)]);
      if (cells_.empty() || !planMove(begin + k * slot, slot)) {
        std::ostringstream why;
        why << "move planned in [" << begin + k * slot << ", " << begin + (k + 1) * slot
            << ") s: no object, time and place met the rules (free, unseen or in view, seen after)";
        plan_.dropped.push_back(why.str());
      }
    }
    for (std::size_t m = 0; m < plan_.moves.size(); ++m) plan_.moves[m].id = static_cast<int>(m) + 1;
    return plan_;
  }

 private:
  /// Places are taken where `free` holds free from now on.
  void useFreeSpace(const FreeSpace& free) {
    free_ = &free;
    cells_.clear();
    const double min_r = spec_.min_diameter / 2;
    for (int y = 0; y < free.size_y; ++y) {
      for (int x = 0; x < free.size_x; ++x) {
        const Vec2 c{free.x_min + (x + 0.5) * free.resolution,
                     free.y_min + (y + 0.5) * free.resolution};
        if (placeOk(c, min_r)) cells_.push_back(c);
      }
    }
  }

  bool placeOk(Vec2 p, double r) const {
    return free_->clearanceAt(p) >= r + spec_.wall_clearance_m &&
           free_->pathDistanceAt(p) >= r + spec_.path_clearance_m;
  }

  Vec2 sample() {
    const Vec2 c = cells_[static_cast<std::size_t>(rng_.uniform() * cells_.size())];
    return {c.x + (rng_.uniform() - 0.5) * free_->resolution,
            c.y + (rng_.uniform() - 0.5) * free_->resolution};
  }

  std::size_t firstScanAt(double t) const { return sim::firstScanAt(scans_, t); }

  /// Whether the disc is seen enough (Sightings::enough) from t0 on, before t1.
  bool seenEnough(Vec2 c, double r, double t0, double t1) const {
    const std::size_t a = firstScanAt(t0), b = firstScanAt(t1);
    std::vector<int> beams(b - a, 0);
    for (std::size_t s = a; s < b; ++s) beams[s - a] = beamsOnDisc(scans_[s], c, r, spec_.counted_range_m);
    return sightings(scans_, t0, t1, spec_.seen_beams, [&](std::size_t s) { return beams[s - a]; })
        .enough(spec_);
  }

  /// The time of the scan that is the spec.seen_scans-th to see the disc from t0 on, before t1;
  /// infinity when there is none.
  double seenBy(Vec2 c, double r, double t0, double t1) const {
    int seen = 0;
    for (std::size_t s = firstScanAt(t0); s < scans_.size() && scans_[s].t < t1; ++s) {
      if (beamsOnDisc(scans_[s], c, r, spec_.counted_range_m) >= spec_.seen_beams &&
          ++seen >= spec_.seen_scans) {
        return scans_[s].t;
      }
    }
    return std::numeric_limits<double>::infinity();
  }

  bool unseen(Vec2 c, double r, double t0, double t1) const {
    for (std::size_t s = firstScanAt(t0); s < scans_.size() && scans_[s].t <= t1; ++s) {
      if (beamsOnDisc(scans_[s], c, r) > 0) return false;
    }
    return true;
  }

  /// At least half the scans of the glide see the cylinder where it is then.
  bool inView(Vec2 a, Vec2 b, double r, double t0, double t1) const {
    int n = 0, seen = 0;
    for (std::size_t s = firstScanAt(t0); s < scans_.size() && scans_[s].t <= t1; ++s, ++n) {
      const double f = (scans_[s].t - t0) / std::max(1e-9, t1 - t0);
      seen += beamsOnDisc(scans_[s], {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)}, r,
                          spec_.counted_range_m) >= spec_.seen_beams;
    }
    return n > 0 && 2 * seen >= n;
  }

  bool apart(Vec2 p, double r, std::size_t self, double t) const {
    for (std::size_t j = 0; j < plan_.objects.size(); ++j) {
      if (j == self) continue;
      const double need = r + plan_.objects[j].diameter / 2 + kObjectGap;
      if (distance(p, addedPositionAt(plan_, j, t)) < need) return false;
    }
    return true;
  }

  bool segmentOk(Vec2 a, Vec2 b, double r) const {
    const int steps = static_cast<int>(std::ceil(distance(a, b) / 0.05));
    for (int i = 0; i <= steps; ++i) {
      const double f = static_cast<double>(i) / std::max(1, steps);
      if (!placeOk({a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)}, r)) return false;
    }
    return true;
  }

  void placeObjects(double first_move) {
    if (cells_.empty()) throw std::invalid_argument("no free place far enough from walls and path");
    const int n = spec_.objects;
    for (int k = 0; k < n; ++k) {
      AddedObject o;
      o.id = k + 1;
      o.diameter = n == 1 ? spec_.min_diameter
                          : spec_.min_diameter + (spec_.max_diameter - spec_.min_diameter) * k / (n - 1);
      o.diameter = std::round(o.diameter * 1000) / 1000;
      const double r = o.diameter / 2;
      bool placed = false;
      // Seen before the first move when possible, so that S holds it where it starts.
      for (int i = 0; i < kStartTries && !placed; ++i) {
        const Vec2 p = sample();
        if (!placeOk(p, r) || !apart(p, r, plan_.objects.size(), 0)) continue;
        if (i < kStartTries / 2 && !std::isfinite(seenBy(p, r, scans_.front().t, first_move))) continue;
        o.start = p;
        placed = true;
      }
      if (!placed) {
        throw std::invalid_argument("no free place for object " + std::to_string(o.id) +
                                    " (diameter " + std::to_string(o.diameter) + " m)");
      }
      plan_.objects.push_back(o);
    }
  }

  /// Objects by how long ago they last moved (never first), those free to move only.
  std::vector<std::size_t> movable(double t) const {
    std::vector<std::size_t> order;
    for (std::size_t k = 0; k < plan_.objects.size(); ++k) {
      if (free_after_[k] <= t) order.push_back(k);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return last_move_[a] < last_move_[b]; });
    return order;
  }

  bool tryPlace(std::size_t k, double t0, double slot) {
    const double r = plan_.objects[k].diameter / 2, t1 = t0 + spec_.glide_s;
    const Vec2 from = addedPositionAt(plan_, k, t0);
    const bool glide = spec_.glide_s > 0;
    if (!glide && !unseen(from, r, t0 - kJumpUnseen, t0 + kJumpUnseen)) return false;
    for (int i = 0; i < kPlaceTries; ++i) {
      const Vec2 to = sample();
      const double d = distance(from, to);
      if (d < 2 * r + 0.3 || !placeOk(to, r) || !apart(to, r, k, t0) || !apart(to, r, k, t1)) continue;
      if (glide && (d < kGlideMin || d > kGlideMax || !segmentOk(from, to, r) ||
                    !inView(from, to, r, t0, t1))) {
        continue;
      }
      if (!glide && !unseen(to, r, t0 - kJumpUnseen, t0 + kJumpUnseen)) continue;
      const double seen = seenBy(to, r, t1, t1 + 2 * slot);
      if (!std::isfinite(seen) || !seenEnough(to, r, t1, seen + 1e-6)) continue;
      if (!clearOfTheLog(scans_, to, r, t1, seen + kWindowS)) continue;
      plan_.moves.push_back({0, plan_.objects[k].id, t0, t1, from, to});
      free_after_[k] = seen;
      last_move_[k] = t0;
      return true;
    }
    return false;
  }

  bool planMove(double window, double slot) {
    for (int i = 0; i < kTimeTries; ++i) {
      const double t0 = window + rng_.uniform() * slot;
      for (std::size_t k : movable(t0)) {
        if (tryPlace(k, t0, slot)) {
          std::stable_sort(plan_.moves.begin(), plan_.moves.end(),
                           [](const AddedMove& a, const AddedMove& b) { return a.t_start < b.t_start; });
          return true;
        }
      }
    }
    return false;
  }

  const std::vector<ScanGeometry>& scans_;
  const std::vector<FreeSpace>& all_free_;
  const FreeSpace* free_ = nullptr;
  const AddObjectsSpec& spec_;
  Rng rng_;
  AddedPlan plan_;
  std::vector<Vec2> cells_;
  std::vector<double> free_after_, last_move_;
};

}  // namespace

AddedPlan planAddedObjects(const std::vector<ScanGeometry>& scans,
                           const std::vector<FreeSpace>& free, const AddObjectsSpec& spec) {
  return Planner(scans, free, spec).plan();
}

}  // namespace dynamap::sim
