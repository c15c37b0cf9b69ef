#pragma once
// Pose estimation from odometry and scans alone (section [slam]): a front end that matches each
// scan against a submap of the scans before it, and a pose graph whose loop closures, found by
// matching scans against older submaps, are optimised as the run goes (PoseGraph).
//
// Front end: the odometry increment since the last scan, applied to the last front-end pose,
// is the guess; ScanMatcher (grid search plus ICP, keeping odometry along directions the walls
// do not pin down) aligns the scan to the static map S of the oldest active submap. Two
// submaps are active at once, each started when the other is half built, as in Cartographer:
// the one matched against always holds at least half a submap of scans.
// Back end: a node per scan; an odometry edge between consecutive nodes, a scan-match edge from
// the submap's anchor to each scan matched, and loop-closure edges from older submaps' anchors.
// A loop closure is searched for every loop_every_m of path, against finished submaps at least
// loop_min_path_m of path back, within a window that grows with the path since the last loop
// closure or, with loop_window_graph, with the path between the scan and the submap through the
// graph (the pose's uncertainty), by branch and bound; a window at least loop_cloud_window_m
// wide is searched with the recent scans' hits (as a tie is), not the scan's alone. A closure is
// proposed when the best pose scores loop_min_score and no pose far from it scores nearly as
// well (loop_ambiguity_ratio: a symmetric corridor is no evidence); the optimiser's gate rejects
// what is still inconsistent. One farther than loop_optimise_m from the estimate is optimised at
// once.
//
// Tied to a prior map (tieTo, a later session against an earlier one's S): the log's first pose
// is the start found in the prior map's frame, and every loop_every_m of path the hits of the
// last submap_length_m of path (at most submap_max_scans scans, as the front end laid them out)
// are searched in the prior's likelihood field, as a loop closure is in a submap's (window
// growing with the path since the last tie up to tie_max_window_m, loop_min_score, the ambiguity
// test), around where the last tie put the trajectory; a tie is an edge from node 0 (held fixed
// at the start) to the scan, of loop_sigma's weight, gated as loop closures are: a place the
// building changed at does not drag the trajectory. Without ties (none accepted) the run is that of
// a first session moved to the start.
//
// Cost: one small search per scan, a field rebuilt every refresh_scans scans, a branch and bound
// per loop attempt, and an optimisation per optimise_every_nodes nodes with a new loop closure.
// Deterministic: single-threaded, the same scans and odometry give the same poses bit for bit.

#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <deque>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dynamap/localization/pose_graph.h"
#include "dynamap/localization/scan_matcher.h"
#include "dynamap/localization/scan_to_scan.h"
#include "dynamap/localization/submap.h"

namespace dynamap {

class IniFile;
template <typename T>
class OptionTable;

struct SlamOptions {
  static constexpr const char* kSection = "slam";

  // Submaps and the front end.
  double submap_length_m = 6.0;      ///< path a submap covers (0.1, 100]
  int submap_max_scans = 200;        ///< ... or at most this many scans [2, 100000]
  double occupied_threshold = 0.65;  ///< submap cells above this P(occ) are walls (0.5, 1)
  double field_sigma_m = 0.05;       ///< width of the likelihood field (0, 1]
  int point_stride = 2;              ///< every n-th beam is matched [1, 100]
  double angle_step_deg = 0.5;       ///< heading step of every search (0, 10]
  // Edges (standard deviations).
  double odometry_sigma_per_m = 0.05;    ///< odometry: translation sd per metre (0, 10]
  double odometry_sigma_per_rad = 0.05;  ///< odometry: heading sd per radian turned (0, 10]
  double match_sigma_m = 0.02;           ///< scan-match edges: translation sd (0, 10]
  double match_sigma_deg = 0.5;          ///< ... heading sd (0, 90]
  /// A match with fewer inliers than this has both sds grown by sqrt(this / inliers): its
  /// information is in proportion to its inliers (a scan in the open keeps a handful of points
  /// short of the insertion range). 0 = every match alike. [0, 100000]
  int match_full_inliers = 200;
  double loop_sigma_m = 0.05;   ///< loop closures: translation sd (0, 10]
  double loop_sigma_deg = 1.0;  ///< ... heading sd (0, 90]
  /// Where the submap match fails (or the scan has no hit short of the insertion range), the
  /// scan is matched to the one before it with every return, far ones included
  /// (scan_to_scan.h): in the open, the previous scan's far walls fix the turn that odometry
  /// alone gets wrong. The matched turn replaces odometry's, in the front end and in the edge;
  /// the distance stays odometry's.
  bool scan_to_scan = true;
  double scan_to_scan_sigma_deg = 0.1;  ///< scan-to-scan edges: heading sd (0, 90]
  /// Every scan matched to the one before: the matched turn, taken with this sd, and odometry's,
  /// with its edge's sd, averaged by their variances make the submap match's guess (a large
  /// turn's odometry error otherwise starts the match a degree or more off). 0: only where the
  /// submap match fails. [0, 90]
  double scan_to_scan_guess_sigma_deg = 0.4;
  // Loop closure.
  double loop_every_m = 2.0;           ///< path between loop closure attempts (0, 1000]
  double loop_min_path_m = 10.0;       ///< submaps at least this far back along the path [0, 1e6]
  double loop_max_distance_m = 30.0;   ///< ... whose middle scan is this close (estimate) (0, 1000]
  int loop_max_candidates = 3;         ///< the nearest this many submaps per attempt [1, 100]
  double loop_window_m = 0.3;          ///< search window right after a loop closure [0, 20]
  double loop_window_per_m = 0.03;     ///< ... growing by this per metre of path since [0, 1]
  double loop_max_window_m = 20.0;     ///< ... up to this [0, 20]
  double loop_window_deg = 3.0;        ///< heading window right after a loop closure [0, 180]
  double loop_window_deg_per_m = 0.1;  ///< ... growing by this per metre of path [0, 10]
  double loop_max_window_deg = 10.0;   ///< ... up to this [0, 180]
  // Ties to a prior map (tieTo): searched as loop closures are, but the window may grow larger:
  // where the session leaves the prior's map, nothing but odometry holds the trajectory.
  double tie_max_window_m = 6.0;      ///< a tie's window grows up to this [0, 50]
  double tie_max_window_deg = 10.0;   ///< ... and its heading window up to this [0, 180]
  double loop_min_score = 0.55;       ///< a loop closure's points' mean field value [0, 1]
  double loop_ambiguity_ratio = 0.9;  ///< runner-up / best above this: ambiguous [0, 1]
  double loop_ambiguity_m = 0.4;      ///< runner-ups this far from the best count (0, 20]
  /// The window grows with the path between the scan and the submap through the graph (across
  /// loop closures), not with the path since the last loop closure anywhere.
  bool loop_window_graph = true;
  /// A loop closure this far (m) from the pose's estimate is optimised at once, so that the next
  /// searches start from corrected estimates; 0: only every optimise_every_nodes [0, 1000].
  double loop_optimise_m = 0.2;
  /// A loop search whose window is at least this wide (m) matches the last submap_length_m of
  /// scans (as the ties to a prior map do), not the current scan alone: a wide window holds
  /// more places one scan fits by chance. 0: never [0, 20].
  double loop_cloud_window_m = 3.0;
  // Optimisation.
  int optimise_every_nodes = 1000;  ///< nodes between optimisations with new loops [1, 1e6]
  int max_iterations = 100;         ///< Levenberg-Marquardt iterations per run [1, 10000]
  double loop_gate = 16.0;          ///< chi^2 above which a loop closure is rejected (0, 1e9]
  int max_rounds = 3;               ///< optimise / reject rounds per optimisation [1, 100]
  /// The odometry, not the optimised poses, when it lays the log's scans onto each other better
  /// (global consistency, consistency.h): a log whose odometry is already corrected is kept.
  bool keep_better_odometry = true;

  /// Every key of [slam]: name, member, range, unit, meaning.
  static const OptionTable<SlamOptions>& table();
  /// Strict load: unknown keys, malformed numbers and out-of-range values throw ConfigError.
  void load(const IniFile& ini);
  /// Throws ConfigError ("<source>: [slam] key: why") for the first rule broken.
  void validate(const std::string& source) const;
  /// Writes the section, one key per line with its meaning (reloadable).
  void writeIni(std::ostream& out) const;
};

/// Counts of a run, for summary.json.
struct SlamStats {
  std::size_t scans = 0, matched = 0, fallbacks = 0, submaps = 0;
  /// Scans placed by matching the scan before (scan_to_scan): fallbacks, and scans with no hit
  std::size_t scan_to_scan = 0;
  std::size_t loop_attempts = 0;    ///< (node, submap) pairs searched
  std::size_t loops_proposed = 0;   ///< searches that found a pose scoring loop_min_score
  std::size_t loops_ambiguous = 0;  ///< ... dropped as ambiguous
  std::size_t loops_accepted = 0;   ///< loop edges in the final graph
  std::size_t loops_rejected = 0;   ///< proposed but ambiguous or rejected by the gate
  std::size_t ties_attempted = 0;   ///< searches in the prior map (tieTo)
  std::size_t ties_proposed = 0;    ///< ... that scored loop_min_score
  std::size_t ties_ambiguous = 0;   ///< ... dropped as ambiguous
  std::size_t ties_accepted = 0;    ///< prior-map edges in the final graph
  std::size_t optimisations = 0, iterations = 0;
  double final_error = 0;  ///< chi^2 of the graph after the last optimisation
  bool converged = true;   ///< false: the last optimisation failed, front-end poses are kept
};

class Slam {
 public:
  /// The submaps are DynamicGridMaps of `map` and `insertion` (the run's own options), the front
  /// end a ScanMatcher of `matching`.
  Slam(const SlamOptions& options, const ScanMatchOptions& matching, const DynamicMapOptions& map,
       const InsertionOptions& insertion);
  ~Slam();

  /// Ties the trajectory to a prior map's frame: `prior` is its S's likelihood field (built with
  /// this run's occupied_threshold and field_sigma_m), and the odometry poses given to add() must
  /// start at the start found in it. Call before the first add().
  void tieTo(LikelihoodField prior);
  /// The next scan, taken at odometry pose `odometry`: `rd` is its makeRangeData() at the
  /// insertion options' range and tolerance, as the mapper works it out.
  void add(const mrpt::poses::CPose2D& odometry, const RangeData& rd);
  /// The last optimisation. Poses are final afterwards.
  void finish();

  /// One pose per scan added, in order: optimised, or the front end's when the last
  /// optimisation did not converge.
  std::vector<mrpt::poses::CPose2D> poses() const;
  const PoseGraph& graph() const { return graph_; }
  const SlamStats& stats() const;

 private:
  /// The scan's pose: matched against the oldest active submap (when it has `hits`; from
  /// `guess` with its turn averaged with the scan-to-scan match's, scan_to_scan_guess_sigma_deg),
  /// or else to the scan before it (scan_to_scan, setting last_step_matched_), or `guess`.
  mrpt::poses::CPose2D frontEnd(const mrpt::poses::CPose2D& guess, const RangeData& rd,
                                const ScanReturns& returns, bool hits);
  /// The edge from the scan before to the one just placed: odometry's increment `inc`, or with
  /// last_step_matched_ the front end's `step` (odometry's distance, the matched turn).
  PoseEdge stepEdge(const mrpt::poses::CPose2D& inc, const mrpt::poses::CPose2D& step) const;
  /// The scan-match edge from `anchor` to scan `i` (`z`: i's pose in anchor's frame), its sds
  /// grown for a match of few inliers (match_full_inliers).
  PoseEdge matchEdge(std::size_t anchor, std::size_t i, const mrpt::poses::CPose2D& z) const;
  /// [rad] odometry's heading sd over a step that turned `turn` (its edge's).
  double odometryHeadingSigma(double turn) const;
  /// The scan's `returns` matched to the scan before (previous_) from `odometry`'s increment;
  /// not matched when either has no returns.
  ScanToScanResult matchPrevious(const ScanReturns& returns,
                                 const mrpt::poses::CPose2D& odometry) const;
  void updateSubmaps(const RangeData& rd);
  /// Keeps node's hits among the recent scans (the last submap_length_m of path).
  void remember(std::size_t node, const std::vector<mrpt::math::TPoint2D>& pts);
  /// The loop search and the tie to a prior map, each every loop_every_m of path.
  void searchEvery(const std::vector<mrpt::math::TPoint2D>& pts);
  /// `cloud` is what the searches match (`pts`, the scan's hits, or the recent scans').
  void searchLoops(const std::vector<mrpt::math::TPoint2D>& pts,
                   const std::vector<mrpt::math::TPoint2D>& cloud);
  /// Whether a loop closure was added; `moved_m`: how far it lies from the pose's estimate.
  bool tryLoop(const Submap& s, const std::vector<mrpt::math::TPoint2D>& pts,
               const std::vector<mrpt::math::TPoint2D>& cloud, double uncertain_m, double& moved_m);
  /// A search's window (m) for a pose this uncertain (m of path): loop_window_m, growing by
  /// loop_window_per_m, up to max_m.
  double searchWindow(double uncertain_m, double max_m) const;
  /// A prior-map edge to the last node, when the search finds one place.
  void tryTie(const std::vector<mrpt::math::TPoint2D>& pts);
  /// The hits of the scans of the last submap_length_m of path, in the last scan's frame (as
  /// the front end laid them out): outdoors one scan holds too few to be placed alone.
  std::vector<mrpt::math::TPoint2D> recentPoints() const;
  /// The best place of `pts` within the window that `uncertain_m` of path opens around `guess`
  /// in `field` (at most `max_m` and `max_deg` wide), sharpened; false (counted in `proposed`,
  /// `ambiguous`) below loop_min_score or when another place scores nearly as well.
  bool searchPlace(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                   const mrpt::poses::CPose2D& guess, double uncertain_m, double max_m,
                   double max_deg, std::size_t& proposed, std::size_t& ambiguous,
                   mrpt::poses::CPose2D& found) const;
  void optimise();

  SlamOptions o_;
  ScanMatcher matcher_;
  DynamicMapOptions map_options_;
  InsertionOptions insertion_;
  PoseGraph graph_;
  std::vector<mrpt::poses::CPose2D> front_;  // front-end poses
  std::vector<double> path_;                 // path length at each node
  mrpt::poses::CPose2D last_odometry_;
  std::deque<std::unique_ptr<Submap>> active_;
  std::vector<std::unique_ptr<Submap>> finished_;
  std::deque<double> active_start_;  // path length at each active submap's anchor
  double last_attempt_path_ = 0, last_closure_path_ = 0;
  std::size_t nodes_at_last_optimise_ = 0;
  bool pending_loops_ = false;
  bool last_match_ok_ = false;
  std::size_t last_match_inliers_ = 0;  // the last submap match's, when last_match_ok_
  bool last_step_matched_ = false;      // the last scan was placed by scan_to_scan
  ScanReturns previous_;                // the last scan's returns (scan_to_scan), if it was usable
  std::unique_ptr<const LikelihoodField> prior_;  // tieTo's
  mrpt::poses::CPose2D prior_offset_;  // the prior's frame from the graph's, at the last tie
  double last_tie_attempt_ = 0, last_tie_path_ = 0;
  std::deque<std::pair<std::size_t, std::vector<mrpt::math::TPoint2D>>> recent_;  // node, hits
  mutable SlamStats stats_;
};

}  // namespace dynamap
