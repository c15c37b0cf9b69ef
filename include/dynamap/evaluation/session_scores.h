#pragma once
// Scores a session's change report (changes.csv of `dynamap map --prior`) against the
// simulator's truth of what changed before that session (NAME.changes.csv). Pure functions over
// plain rows; the readers are in result_files.h. Definitions: docs/evaluation.md, "Sessions".

#include <string>
#include <vector>

namespace dynamap {

/// A place that may be unknown (an empty CSV field).
struct MaybePoint {
  bool known = false;
  double x = 0, y = 0;
};

/// One change, of the truth or of a report; kinds as in changes.csv.
struct ScoredRow {
  int session = 0;  ///< truth: the session it is seen in; a report: 0
  std::string kind;
  int id = 0;  ///< truth: the scenario's object or wall number; a report: dynamap's id
  double size = 0;
  MaybePoint from, to;  ///< a truth wall: its two ends; a reported region: its centre
};

/// A row of the previous session's object table (objects.csv): who was where.
struct TableRow {
  int id = 0;
  double size = 0, cx = 0, cy = 0;
};

enum class ChangeVerdict {
  Found,      ///< the right kind, at the right place(s), under the right id
  WrongId,    ///< the right kind at the right place(s), another id
  Misplaced,  ///< the right kind and object, a place off (a move's origin or its end)
  Missed,     ///< nothing reported for it
};
const char* verdictName(ChangeVerdict v);

struct ScoredChange {
  ScoredRow truth;
  ChangeVerdict verdict = ChangeVerdict::Missed;
  int expected_id = -1;  ///< the id the report must carry (the prior table's), -1: any
  int reported = -1;     ///< index into the report of the row it was matched with
};

struct SessionScore {
  int session = 0;
  std::vector<ScoredChange> changes;  ///< every truth change, in the truth's order
  std::vector<int> false_changes;     ///< indices into the report of rows matching no change
  int count(ChangeVerdict v) const;
};

struct ChangeMatchOptions {
  double place_radius = 0.5;  ///< [m] a reported place this close to the truth's is right
};

/// Scores `report` (one session's changes.csv) against the truth's rows of that session.
/// An object change's place is its new place (moved, new) or its old one (gone); a move must
/// also start within the radius of the truth's origin. The right id of an object the previous
/// session's table held at the change's origin (nearest row within the radius) is that row's;
/// a new object's id must be new to that table; otherwise any id is right. A structure change
/// is found by a region of its kind whose centre lies within the radius of the wall; further
/// regions along the same wall are parts of it, not false changes.
SessionScore scoreSession(int session, const std::vector<ScoredRow>& truth,
                          const std::vector<ScoredRow>& report,
                          const std::vector<TableRow>& previous_table,
                          const ChangeMatchOptions& options = {});

}  // namespace dynamap
