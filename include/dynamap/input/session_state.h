#pragma once
// The state one mapping session leaves for the next (`dynamap map --prior`): the static map S,
// the object table with ids, sizes and places, and where the session ended, all in the map's
// frame. A run writes it as session.json beside its outputs; a later run over a new log of the
// same building starts from it and reports what changed (docs/sessions.md).
//
// The file is JSON; the grid's cells are MRPT's int8 log-odds, zlib-compressed and base64-coded
// in one string. readSessionState() trusts nothing in it: every error is an InputError naming
// the file and the key, and no allocation is larger than the grid the file's geometry describes,
// itself bounded by the caller's largest map.

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace dynamap {

/// One row of the object table as the next session inherits it.
struct SessionObject {
  int id = 0;  ///< 1, 2, ...: rows are stored in id order, every id once
  /// "present", "absent", or one of the states no table lists ("withdrawn", "relabeled",
  /// "retracted"): kept so that ids stay where they were.
  std::string state;
  double cx = 0, cy = 0, size = 0;  ///< [m] its last known place and its size
  int n_moves = 0;
  double first_seen_t = 0, last_seen_t = 0;  ///< [s] in the time of the session that saw it
};

struct SessionState {
  static constexpr int kVersion = 1;
  int sessions = 1;  ///< how many sessions it holds (1 after the first run)
  /// The grid of S: cell (0, 0)'s lower-left corner at (x_min, y_min), size_x * size_y cells of
  /// `resolution` metres, row by row from y_min up, each MRPT's int8 log-odds of being free.
  double x_min = 0, y_min = 0, resolution = 0.05;
  unsigned size_x = 0, size_y = 0;
  std::vector<std::int8_t> static_cells;
  std::vector<SessionObject> objects;
  double last_x = 0, last_y = 0, last_phi = 0;  ///< the robot's last pose [m m rad]
  double last_t = 0;                           ///< and its time [s]
};

/// Writes `state` as JSON (cells compressed). Throws std::runtime_error when the cells do not
/// match the geometry.
void writeSessionState(const SessionState& state, std::ostream& out);

/// Reads the session state at `path` (a session.json, or the output directory holding one).
/// `max_cells` bounds size_x * size_y (the caller's largest map); the file itself may be at
/// most 1 GiB. Throws InputError naming the file and the key on any fault.
SessionState readSessionState(const std::string& path, std::uint64_t max_cells);
/// The same from text already read; `name` is the file's name for messages.
SessionState parseSessionState(const std::string& text, const std::string& name,
                               std::uint64_t max_cells);

}  // namespace dynamap
