#include "dynamap/pipeline/people_objects.h"

#include <algorithm>
#include <cmath>

namespace dynamap {

void PeopleObjects::update(const PersonTracker& people, ObjectTracker& objects,
                           std::size_t first_event, double t, std::size_t scan_index) {
  walk_offs_.erase(std::remove_if(walk_offs_.begin(), walk_offs_.end(),
                                  [t](const Place& p) { return t > p.until_t; }),
                   walk_offs_.end());
  while (!gone_.empty() && t - gone_.front().t > kWalkOffWindowS) gone_.pop_front();
  while (!fresh_.empty() && t - fresh_.front().t > kPairWindowS) fresh_.pop_front();
  // This scan's events first (withdraw() adds events: only the ones there were are read).
  const std::size_t end = objects.events().size();
  for (std::size_t i = first_event; i < end; ++i) {
    const EventRecord e = objects.events()[i];
    const Sighting s{e.object_id, t, e.cx, e.cy, e.size};
    switch (e.event) {
      case ObjectEvent::New:
      case ObjectEvent::Moved:
      case ObjectEvent::Reappeared:
        placed(people, s);
        break;
      case ObjectEvent::Disappeared:
      case ObjectEvent::Retracted:  // gone soon after it came: its leg-sized partner may be too
        judgeGone(objects, s, scan_index);
        break;
      case ObjectEvent::Withdrawn:
      case ObjectEvent::Relabeled:  // the new id has its own event (new, moved...) too
        break;
    }
  }
  addWalkOffs(people, objects, t, scan_index);
}

void PeopleObjects::placed(const PersonTracker& people, const Sighting& s) {
  Record& r = records_[s.id];
  ++r.placements;
  r.placed_t = s.t;
  r.current_person_like = false;
  for (const auto& [x, y] : people.standingLegs()) {
    if (std::hypot(s.x - x, s.y - y) <= options_.static_clearance) markPersonLike(s.id);
  }
  if (!legSized(s.size)) return;
  // Where people stood before, they stand again (a counter, a door): legs, as then.
  if (nearPersonPlace(s.x, s.y)) markPersonLike(s.id);
  // Two leg-sized objects that appear together, side by side: a pair of legs.
  for (const Sighting& other : fresh_) {
    if (other.id != s.id && legSized(other.size) &&
        std::hypot(other.x - s.x, other.y - s.y) <= options_.leg_pair_distance) {
      markPersonLike(s.id);
      markPersonLike(other.id);
    }
  }
  fresh_.push_back(s);
}

void PeopleObjects::markPersonLike(int id) {
  Record& r = records_[id];
  if (r.current_person_like) return;
  r.current_person_like = true;
  ++r.person_like;
}

bool PeopleObjects::allPersonLike(int id) const {
  const auto it = records_.find(id);
  return it != records_.end() && it->second.placements > 0 &&
         it->second.person_like == it->second.placements;
}

void PeopleObjects::addWalkOffs(const PersonTracker& people, ObjectTracker& objects, double t,
                                std::size_t scan_index) {
  if (people.walkOffs().empty()) return;
  for (const PersonTracker::WalkOff& w : people.walkOffs()) {
    walk_offs_.push_back({w.born_x, w.born_y, w.since_t, t + kWalkOffWindowS});
    walk_offs_.push_back({w.from_x, w.from_y, w.since_t, t + kWalkOffWindowS});
  }
  // Gone already: the legs' cells faded before the person was known to walk.
  std::vector<int> ids;
  for (const Sighting& g : gone_) {
    if (walkedOff(g)) markPersonLike(g.id);
    if (allPersonLike(g.id)) ids.push_back(g.id);
  }
  for (const int id : ids) withdraw(objects, id, t, scan_index);
}

bool PeopleObjects::walkedOff(const Sighting& g) const {
  const auto it = records_.find(g.id);
  if (it == records_.end()) return false;
  for (const Place& p : walk_offs_) {
    // Placed there only since the person stood there: not an object they came to.
    if (it->second.placed_t >= p.since_t &&
        std::hypot(g.x - p.x, g.y - p.y) <= options_.static_clearance)
      return true;
  }
  return false;
}

void PeopleObjects::judgeGone(ObjectTracker& objects, const Sighting& g, std::size_t scan_index) {
  if (walkedOff(g)) markPersonLike(g.id);
  if (legSized(g.size)) {  // two leg-sized objects side by side that go together: legs
    for (const Sighting& other : gone_) {
      if (other.id != g.id && legSized(other.size) && g.t - other.t <= kPairWindowS &&
          std::hypot(other.x - g.x, other.y - g.y) <= options_.leg_pair_distance) {
        markPersonLike(g.id);
        markPersonLike(other.id);
        if (allPersonLike(other.id)) withdraw(objects, other.id, g.t, scan_index);
        break;
      }
    }
  }
  // Every place it was ever reported at was a person's: it never was an object.
  if (allPersonLike(g.id)) {
    withdraw(objects, g.id, g.t, scan_index);
  } else {
    gone_.push_back(g);
  }
}

CellKey PeopleObjects::placeCell(double x, double y) const {
  // Cells of a map at most max_map_size_m wide: their indices fit in an int.
  const double side = options_.leg_pair_distance;
  return cellKey(static_cast<int>(std::floor(x / side)), static_cast<int>(std::floor(y / side)));
}

bool PeopleObjects::nearPersonPlace(double x, double y) const {
  const double side = options_.leg_pair_distance;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const auto it = person_places_.find(placeCell(x + dx * side, y + dy * side));
      if (it == person_places_.end()) continue;
      for (const auto& [px, py] : it->second) {
        if (std::hypot(px - x, py - y) <= 0.5 * side) return true;
      }
    }
  }
  return false;
}

void PeopleObjects::withdraw(ObjectTracker& objects, int id, double t, std::size_t scan_index) {
  if (objects.withdraw(id, t, scan_index)) {
    const ShapeEstimate& s = objects.objects()[static_cast<std::size_t>(id - 1)].shape;
    auto& cell = person_places_[placeCell(s.cx, s.cy)];
    if (cell.size() < kPlacesPerCell) cell.emplace_back(s.cx, s.cy);
  }
  records_.erase(id);
  gone_.erase(
      std::remove_if(gone_.begin(), gone_.end(), [id](const Sighting& g) { return g.id == id; }),
      gone_.end());
}

}  // namespace dynamap
