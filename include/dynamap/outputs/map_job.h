#pragma once
// One whole mapping job, shared by `dynamap map` and `dynamap eval`: a log in, every output file
// of docs' "Outputs" out. Opens the source, runs the per-scan step over it, streams tracks.csv
// and poses.txt, builds the plain MRPT baseline and the frames when asked, and writes the maps,
// the tables and summary.json at the end — also when the input ended in a fault.

#include <cstddef>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include "dynamap/input/bag_source.h"
#include "dynamap/input/carmen_reader.h"
#include "dynamap/mapping/plain_grid.h"
#include "dynamap/pipeline/mapper.h"
#include "dynamap/pipeline/session_start.h"
#include "dynamap/pipeline/slam_run.h"

namespace dynamap {

/// Thrown by runMapJob when MapJob::cancelled said so: nothing of the run was committed.
class RunCancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MapJob {
  std::string input;  ///< the log
  /// Created if needed; must be writable and not in use by another run (checked before any
  /// work). The run's outputs replace the previous run's there as one set (OutputStaging).
  std::string out_dir;
  MapConfig config;
  CarmenOptions carmen;   ///< for CARMEN input
  BagOptions bag;         ///< for ROS bag input
  bool baseline = true;   ///< also build the plain MRPT grid (mrpt_plain.png, summary.json)
  long frames_every = 0;  ///< > 0: frames/NNNNNN.png every this many scans, and timelapse.mp4
  /// An earlier run's output directory (or its session.json): this run continues that session
  /// (Mapper::continueFrom) and writes changes.csv and changes.png. Empty: a first session.
  std::string prior;
  /// Where the first scan was taken, in the prior's frame: every pose is moved rigidly to
  /// start there. Not given, with a prior and poses from odometry (odometry, scan_matching,
  /// slam), the start is searched for in the prior's map (locateStart); poses that are in the
  /// prior's frame already (ground truth, simplemap, fixed) are kept as they are.
  std::optional<mrpt::poses::CPose2D> initial_pose;
  /// Called after every scan with the share of the input read (negative: unknown) and the
  /// scans mapped so far; may be empty.
  std::function<void(double fraction, std::size_t scans_used)> progress;
  /// Pose source slam: called when pass `pass` (1: the trajectory, 2: the mapping) begins, and
  /// with pass 0 when both are done; `progress` then reports each pass. May be empty.
  std::function<void(int pass)> on_pass;
  /// Asked after every scan and before the outputs are committed (e.g. a signal came): true
  /// ends the run with RunCancelled, the output directory as it was. May be empty.
  std::function<bool()> cancelled;
  /// Called once every scan is mapped, before the outputs are written, with the mapper whose
  /// maps and tables they are written from (e.g. to copy S and D into memory). May be empty.
  std::function<void(const Mapper&)> on_mapped;
};

struct MapJobResult {
  std::string pose_source;  ///< the one used (never auto)
  std::string pose_detail;  ///< which of the format's streams (ScanSource::poseDetail)
  RunCounts counts;
  SourceStats source_stats;
  bool scan_matching = false;
  ScanMatchCounts scan_match_counts;
  std::optional<PlainComparison> baseline;  ///< with MapJob::baseline
  double wall_s = 0;                        ///< the run without the baseline
  double baseline_wall_s = 0;               ///< the baseline alone
  InputOutcome outcome;  ///< fault: the input ended in one, outputs cover what came before
  /// Pose source slam: pass 1's counts and time (wall_s is then pass 2's).
  std::optional<SlamStats> slam;
  /// With a prior and no initial pose on odometry-based poses: where the search placed the start.
  std::optional<GlobalPlacement> start;
  double slam_wall_s = 0;
};

/// Runs the job. Throws InputError when the input cannot be opened, std::runtime_error for an
/// output that cannot be written and RunCancelled; in each case the output directory keeps the
/// previous run's outputs and nothing of this one.
MapJobResult runMapJob(const MapJob& job);

}  // namespace dynamap
