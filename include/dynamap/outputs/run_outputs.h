#pragma once
// Every output of one mapping run: the pictures, the grids, the tables and summary.json.

#include <string>

#include "dynamap/input/scan_source.h"
#include "dynamap/mapping/plain_grid.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/pipeline/slam_run.h"

namespace dynamap {

/// Writes every output of `dynamap map` into `dir` (which must exist).
struct OutputInfo {
  std::string input;
  double wall_s = 0;
  InputOutcome outcome;
  /// The plain MRPT grid of the same scans (nullptr: none): compared with S in summary.json
  /// and drawn as mrpt_plain.png.
  const PlainGrid* baseline = nullptr;
  double baseline_wall_s = 0;  ///< time spent building it
  PlainComparison baseline_cells;  ///< with baseline: comparePlain(S, it), for summary.json
  /// Pass 1 of pose source slam (nullptr: not used): its counts go to summary.json's "slam"
  /// block and its pose graph to graph.g2o.
  const SlamRun* slam = nullptr;
};
void writeMapOutputs(const std::string& dir, const Mapper& mapper, const ScanSource& source,
                     const OutputInfo& info);

}  // namespace dynamap
