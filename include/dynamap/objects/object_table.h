#pragma once
// The object table: one row per object ever reported, and the events that changed it.

#include <cstddef>
#include <string>
#include <vector>

#include "dynamap/objects/shape.h"

namespace dynamap {

/// Withdrawn: it was a person standing, who walked off (the table no longer holds it).
enum class ObjectState { Present, Absent, Withdrawn };
const char* toString(ObjectState s);

enum class ObjectEvent { New, Moved, Disappeared, Reappeared, Withdrawn };
const char* toString(ObjectEvent e);

struct PositionRecord {
  double t, cx, cy;
};

/// One row of the object table.
struct TrackedObject {
  int id = 0;           ///< 1, 2, ... in order of first report
  std::string label;    ///< "object<id>"
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
};

}  // namespace dynamap
