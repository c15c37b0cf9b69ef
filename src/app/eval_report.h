#pragma once
// The reports of `dynamap eval`: one evaluated result as the terminal table, report.md and
// metrics.json (fixed key order and number formats: the same figures give the same bytes), and
// the --summary table that reads several metrics.json back.

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "dynamap/evaluation/evaluation.h"
#include "dynamap/outputs/json.h"

namespace dynamap::app {

/// Every figure of one evaluated result, and what it was scored from.
struct Evaluation {
  std::string scenario, truth, result;
  bool have_tracks = false;
  bool real_scans = false;  // no scenario: objects added to a real log
  bool have_own = false;    // real scans: the unedited log's own object rows (PREFIX.own.csv)
  std::size_t moves = 0;
  ObjectScores objects;
  std::size_t observed = 0;
  CellScores dynamap, plain;
  PrecisionRecall union_pr;
  double object_threshold = 0.85;
  std::vector<std::string> notes;
  bool have_people = false;              // the result has people.csv
  MotScores mot;                         // its CLEAR MOT against the person truth
  bool have_poses = false;               // the result has poses.txt
  TrajectoryError trajectory, odometry;  // of poses.txt and of the log's raw odometry
};

/// A fixed-format number; NaN prints as `nan_text`.
std::string num(double v, int decimals, const std::string& nan_text = "null");
/// `v` with `decimals` fixed decimals as a JSON number; null when it is not a number.
Json jnum(double v, int decimals);
/// The table printed on the terminal, the paper's Table 3 column beside it where one matches.
void printTable(std::ostream& o, const Evaluation& ev);
/// metrics.json: every figure under a unique key (--summary reads them back).
void writeMetricsJson(std::ostream& o, const Evaluation& ev);
/// report.md: the table, the notes and the result's pictures.
void writeReport(std::ostream& o, const Evaluation& ev);
/// --summary DIR...: one table of the evaluated results beside the paper's; an error names the
/// metrics.json and the key it lacks. Returns the exit code.
int runSummary(const std::vector<std::string>& dirs, std::ostream& o);
/// --sessions: the change report of each session after the first (dirs in session order)
/// against the truth's PREFIX.changes.csv; prints each score and writes it to the session's
/// changes_score.json.
int scoreSessions(const std::vector<std::string>& dirs, const std::string& truth_prefix,
                  std::ostream& o);

}  // namespace dynamap::app
