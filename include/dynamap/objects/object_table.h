#pragma once
// The object table: one row per object ever reported, and the events that changed it.

#include <cstddef>
#include <string>
#include <vector>

#include "dynamap/objects/shape.h"

namespace dynamap {

/// Withdrawn: it was a person standing, who walked off. Relabeled: a provisional identity
/// found to be another object's (or a new one's). Retracted: a provisional report whose place
/// was seen empty before its size settled, or a new object's seen empty within min_rest_s. The table holds none of these three.
enum class ObjectState { Present, Absent, Withdrawn, Relabeled, Retracted };
const char* toString(ObjectState s);
/// Whether objects.csv lists an object in state `s` (present or absent).
inline bool listedInTable(ObjectState s) {
  return s == ObjectState::Present || s == ObjectState::Absent;
}

/// Relabeled: the object first reported as `from_id` is this one (`object_id`). Retracted: a
/// report withdrawn (its place seen empty before its size settled or within min_rest_s).
enum class ObjectEvent { New, Moved, Disappeared, Reappeared, Withdrawn, Relabeled, Retracted };
const char* toString(ObjectEvent e);

struct PositionRecord {
  double t, cx, cy;
};

/// One row of the object table.
struct TrackedObject {
  int id = 0;         ///< 1, 2, ... in order of first report
  std::string label;  ///< "object<id>"
  /// Its shape: while it is tracked, the live estimate of its track (which holds no copy);
  /// once absent, the last one.
  ShapeEstimate shape;
  ObjectState state = ObjectState::Present;
  double first_seen_t = 0, last_seen_t = 0;
  int n_moves = 0;
  double vanished_t = 0;                ///< when it was last marked absent
  std::vector<PositionRecord> history;  ///< where it was found: at new, moved, reappeared
};

struct EventRecord {
  double t;
  std::size_t scan_index;
  int object_id;
  ObjectEvent event;
  double cx, cy, size;
  int from_id = 0;  ///< Relabeled: the provisional id it replaces; else 0
};

}  // namespace dynamap
