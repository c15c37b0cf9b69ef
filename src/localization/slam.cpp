#include "dynamap/localization/slam.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <utility>

#include "dynamap/base/angles.h"
#include "dynamap/base/ini.h"
#include "dynamap/base/option_table.h"
#include "dynamap/localization/field_matcher.h"

namespace dynamap {
namespace {

using O = SlamOptions;

constexpr std::size_t kMaxTiePoints = 200;  // a tie search costs as its points

// The submaps, the loop search's field and the edges' standard deviations.
std::vector<Option<O>> graphRows() {
  return {
      {"submap_length_m", &O::submap_length_m, Range::openClosed(0.1, 100), "m",
       "path a submap covers"},
      {"submap_max_scans", &O::submap_max_scans, Range::closed(2, 100000), "",
       "a submap holds at most this many scans"},
      {"occupied_threshold", &O::occupied_threshold, Range::open(0.5, 1), "",
       "S cells of a finished submap above this P(occ) are walls"},
      {"field_sigma_m", &O::field_sigma_m, Range::openClosed(0, 1), "m",
       "sd of a finished submap's likelihood field around its walls"},
      {"point_stride", &O::point_stride, Range::closed(1, 100), "",
       "every n-th beam is matched in a loop search"},
      {"angle_step_deg", &O::angle_step_deg, Range::openClosed(0, 10), "deg",
       "heading step of a loop search"},
      {"odometry_sigma_per_m", &O::odometry_sigma_per_m, Range::openClosed(0, 10), "",
       "odometry edges: translation sd per metre"},
      {"odometry_sigma_per_rad", &O::odometry_sigma_per_rad, Range::openClosed(0, 10), "",
       "odometry edges: heading sd per radian"},
      {"match_sigma_m", &O::match_sigma_m, Range::openClosed(0, 10), "m",
       "scan-match edges: translation sd"},
      {"match_sigma_deg", &O::match_sigma_deg, Range::openClosed(0, 90), "deg",
       "scan-match edges: heading sd"},
      {"match_full_inliers", &O::match_full_inliers, Range::closed(0, 100000), "",
       "scan-match edges: a match with fewer inliers than this has its sds grown by "
       "sqrt(this / inliers); 0 = every match alike"},
      {"loop_sigma_m", &O::loop_sigma_m, Range::openClosed(0, 10), "m",
       "loop-closure edges: translation sd"},
      {"loop_sigma_deg", &O::loop_sigma_deg, Range::openClosed(0, 90), "deg",
       "loop-closure edges: heading sd"},
      {"scan_to_scan", &O::scan_to_scan, Range{}, "",
       "where the submap match fails, the scan is matched to the one before it with every "
       "return, far ones included, and the turn between them replaces odometry's"},
      {"scan_to_scan_sigma_deg", &O::scan_to_scan_sigma_deg, Range::openClosed(0, 90), "deg",
       "scan-to-scan edges: heading sd (their translation is odometry's)"},
      {"scan_to_scan_guess_sigma_deg", &O::scan_to_scan_guess_sigma_deg, Range::closed(0, 90),
       "deg",
       "every scan is matched to the one before, and its turn, taken with this sd, is averaged "
       "with odometry's as the submap match's guess; 0: only where the submap match fails"},
  };
}

// Loop closure and the optimiser.
std::vector<Option<O>> loopRows() {
  return {
      {"loop_every_m", &O::loop_every_m, Range::openClosed(0, 1000), "m",
       "path between loop closure attempts"},
      {"loop_min_path_m", &O::loop_min_path_m, Range::closed(0, 1e6), "m",
       "only submaps this far back along the path"},
      {"loop_max_distance_m", &O::loop_max_distance_m, Range::openClosed(0, 1000), "m",
       "only submaps whose middle scan lies this close (estimate)"},
      {"loop_max_candidates", &O::loop_max_candidates, Range::closed(1, 100), "",
       "the nearest n such submaps are searched per attempt"},
      {"loop_window_m", &O::loop_window_m, Range::closed(0, 20), "m",
       "loop search window after a loop closure"},
      {"loop_window_per_m", &O::loop_window_per_m, Range::closed(0, 1), "",
       "it grows by this per metre of path since the last one"},
      {"loop_max_window_m", &O::loop_max_window_m, Range::closed(0, 20), "m",
       "the loop search window's upper bound"},
      {"loop_window_deg", &O::loop_window_deg, Range::closed(0, 180), "deg",
       "heading window after a loop closure"},
      {"loop_window_deg_per_m", &O::loop_window_deg_per_m, Range::closed(0, 10), "deg",
       "it grows by this per metre of path"},
      {"loop_max_window_deg", &O::loop_max_window_deg, Range::closed(0, 180), "deg",
       "the heading window's upper bound"},
      {"tie_max_window_m", &O::tie_max_window_m, Range::closed(0, 50), "m",
       "a search in the prior session's map (--prior): its window's upper bound"},
      {"tie_max_window_deg", &O::tie_max_window_deg, Range::closed(0, 180), "deg",
       "... and its heading window's"},
      {"loop_min_score", &O::loop_min_score, Range::closed(0, 1), "",
       "a loop closure's points' mean field value"},
      {"loop_ambiguity_ratio", &O::loop_ambiguity_ratio, Range::closed(0, 1), "",
       "runner-up / best above this: ambiguous"},
      {"loop_ambiguity_m", &O::loop_ambiguity_m, Range::openClosed(0, 20), "m",
       "runner-ups this far from the best count"},
      {"loop_window_graph", &O::loop_window_graph, Range{}, "",
       "the window grows with the path between the scan and the submap through the graph "
       "(across loop closures), not with the path since the last loop closure"},
      {"loop_optimise_m", &O::loop_optimise_m, Range::closed(0, 1000), "m",
       "a loop closure this far from the estimate is optimised at once (0: off)"},
      {"loop_cloud_window_m", &O::loop_cloud_window_m, Range::closed(0, 20), "m",
       "a loop search whose window is at least this wide matches the last submap_length_m of "
       "scans, not the current scan alone (0: never)"},
      {"optimise_every_nodes", &O::optimise_every_nodes, Range::closed(1, 1000000), "",
       "nodes between optimisations (new loops)"},
      {"max_iterations", &O::max_iterations, Range::closed(1, 10000), "",
       "Levenberg-Marquardt iterations per optimisation"},
      {"loop_gate", &O::loop_gate, Range::openClosed(0, 1e9), "",
       "chi^2 above which a loop closure is rejected"},
      {"max_rounds", &O::max_rounds, Range::closed(1, 100), "",
       "optimise-and-reject rounds per optimisation"},
      {"keep_better_odometry", &O::keep_better_odometry, Range{}, "",
       "pass 2 maps on the odometry instead when it lays the scans onto each other better than "
       "the optimised poses (global consistency, as dynamap eval --input scores it)"},
  };
}

}  // namespace

const OptionTable<SlamOptions>& SlamOptions::table() {
  static const OptionTable<O> t(kSection, [] {
    std::vector<Option<O>> rows = graphRows(), more = loopRows();
    rows.insert(rows.end(), more.begin(), more.end());
    return rows;
  }());
  return t;
}

namespace {

Eigen::Matrix3d diagonalInformation(double sigma_xy, double sigma_phi) {
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  info(0, 0) = info(1, 1) = 1.0 / (sigma_xy * sigma_xy);
  info(2, 2) = 1.0 / (sigma_phi * sigma_phi);
  return info;
}

}  // namespace

void SlamOptions::load(const IniFile& ini) {
  table().load(ini, *this);
  validate(ini.name());
}

void SlamOptions::validate(const std::string& source) const {
  table().checkRanges(*this, source);
  if (loop_max_window_m < loop_window_m) {
    rejectValue(source, kSection, "loop_max_window_m", "must be at least loop_window_m");
  }
  if (loop_max_window_deg < loop_window_deg) {
    rejectValue(source, kSection, "loop_max_window_deg", "must be at least loop_window_deg");
  }
  if (tie_max_window_m < loop_window_m) {
    rejectValue(source, kSection, "tie_max_window_m", "must be at least loop_window_m");
  }
  if (tie_max_window_deg < loop_window_deg) {
    rejectValue(source, kSection, "tie_max_window_deg", "must be at least loop_window_deg");
  }
}

void SlamOptions::writeIni(std::ostream& out) const {
  table().write(*this, out);
}

Slam::Slam(const SlamOptions& options, const ScanMatchOptions& matching,
           const DynamicMapOptions& map, const InsertionOptions& insertion)
    : o_(options), matcher_(matching), map_options_(map), insertion_(insertion) {
  o_.validate("slam options");
}

Slam::~Slam() = default;

void Slam::add(const mrpt::poses::CPose2D& odometry, const RangeData& rd) {
  // A scan that is not planar, or whose mount is not finite, is placed by odometry and kept
  // out of the submaps.
  const mrpt::poses::CPose3D& mount = rd.mount;
  const bool usable = rd.planar && std::isfinite(mount.x()) && std::isfinite(mount.y()) &&
                      std::isfinite(mount.yaw());
  std::vector<mrpt::math::TPoint2D> pts;
  if (usable) pts = hitPoints(rd, static_cast<std::size_t>(o_.point_stride));
  ScanReturns returns;
  if (usable && o_.scan_to_scan) returns = ScanReturns::of(rd);
  const std::size_t i = graph_.size();
  ++stats_.scans;
  if (i == 0) {
    front_.push_back(odometry);
    path_.push_back(0);
    graph_.addNode(odometry);
  } else {
    const mrpt::poses::CPose2D inc = odometry - last_odometry_;
    last_step_matched_ = false;
    // A scan with no hit short of the insertion range may still hold far returns.
    const mrpt::poses::CPose2D pose =
        pts.empty() && returns.returns == 0
            ? front_.back() + inc
            : frontEnd(front_.back() + inc, rd, returns, !pts.empty());
    const mrpt::poses::CPose2D step = pose - front_.back();
    path_.push_back(path_.back() + std::hypot(step.x(), step.y()));
    front_.push_back(pose);
    graph_.addNode(graph_.pose(i - 1) + step);
    graph_.addEdge(stepEdge(inc, step));
    if (!active_.empty() && active_.front()->anchor() != i && stats_.matched > 0 &&
        last_match_ok_) {
      graph_.addEdge(
          matchEdge(active_.front()->anchor(), i, pose - front_[active_.front()->anchor()]));
    }
  }
  last_odometry_ = odometry;
  previous_ = std::move(returns);
  if (!pts.empty()) updateSubmaps(rd);
  if ((prior_ || o_.loop_cloud_window_m > 0) && !pts.empty()) remember(i, pts);
  searchEvery(pts);
  if (pending_loops_ &&
      graph_.size() - nodes_at_last_optimise_ >= std::size_t(o_.optimise_every_nodes)) {
    optimise();
  }
}

void Slam::remember(std::size_t node, const std::vector<mrpt::math::TPoint2D>& pts) {
  recent_.emplace_back(node, pts);
  // As a submap: so much path or so many scans (a robot standing still adds no path).
  while (path_.back() - path_[recent_.front().first] > o_.submap_length_m ||
         recent_.size() > static_cast<std::size_t>(o_.submap_max_scans)) {
    recent_.pop_front();
  }
}

void Slam::searchEvery(const std::vector<mrpt::math::TPoint2D>& pts) {
  const bool loop_due = path_.back() - last_attempt_path_ >= o_.loop_every_m;
  const bool tie_due =
      prior_ && !pts.empty() && path_.back() - last_tie_attempt_ >= o_.loop_every_m;
  const bool loop_cloud = loop_due && o_.loop_cloud_window_m > 0 && !pts.empty();
  // The recent scans' cloud once for both searches: it depends on the front end's poses only,
  // which a loop closure's optimisation leaves as they are.
  std::vector<mrpt::math::TPoint2D> cloud;
  if (loop_cloud || tie_due) cloud = recentPoints();
  if (loop_due) {
    last_attempt_path_ = path_.back();
    searchLoops(pts, loop_cloud ? cloud : pts);
  }
  if (tie_due) {
    last_tie_attempt_ = path_.back();
    tryTie(cloud);
  }
}

double Slam::odometryHeadingSigma(double turn) const {
  // A floor keeps the edge invertible on a straight drive.
  return 0.2 * kDegToRad + o_.odometry_sigma_per_rad * std::abs(turn);
}

PoseEdge Slam::stepEdge(const mrpt::poses::CPose2D& inc, const mrpt::poses::CPose2D& step) const {
  const std::size_t i = graph_.size() - 1;
  // Odometry: sd grows with the distance and the turn; a floor keeps it invertible.
  const double d = std::hypot(inc.x(), inc.y());
  const double sigma_xy = 0.01 + o_.odometry_sigma_per_m * d;
  if (last_step_matched_) {  // odometry's distance, the scans' turn
    return {i - 1, i, step, diagonalInformation(sigma_xy, o_.scan_to_scan_sigma_deg * kDegToRad),
            EdgeKind::Odometry};
  }
  return {i - 1, i, inc, diagonalInformation(sigma_xy, odometryHeadingSigma(inc.phi())),
          EdgeKind::Odometry};
}

PoseEdge Slam::matchEdge(std::size_t anchor, std::size_t i, const mrpt::poses::CPose2D& z) const {
  // A match's information grows with its inliers: one of few points (a scan in the open with a
  // handful of returns short of the insertion range) is worth less than one of hundreds.
  const double full = static_cast<double>(o_.match_full_inliers);
  const double inliers = static_cast<double>(std::max<std::size_t>(1, last_match_inliers_));
  const double grow = full > inliers ? std::sqrt(full / inliers) : 1.0;
  return {anchor, i, z,
          diagonalInformation(grow * o_.match_sigma_m, grow * o_.match_sigma_deg * kDegToRad),
          EdgeKind::ScanMatch};
}

ScanToScanResult Slam::matchPrevious(const ScanReturns& returns,
                                     const mrpt::poses::CPose2D& odometry) const {
  if (returns.returns == 0 || previous_.returns == 0) return {odometry};
  const ScanMatchOptions& m = matcher_.options();
  ScanToScanLimits limits;
  limits.max_correction_m = m.max_correction_m;
  limits.max_correction_rad = m.max_correction_deg * kDegToRad;
  // Matched on every scan to sharpen the submap match's guess: a large turn may be off by
  // more than a small one's limit (three of odometry's sds).
  if (o_.scan_to_scan_guess_sigma_deg > 0) {
    limits.max_correction_rad += 3 * o_.odometry_sigma_per_rad * std::abs(odometry.phi());
  }
  limits.min_constraint = m.min_constraint;
  return matchScans(previous_, returns, odometry, limits);
}

mrpt::poses::CPose2D Slam::frontEnd(const mrpt::poses::CPose2D& guess, const RangeData& rd,
                                    const ScanReturns& returns, bool hits) {
  last_match_ok_ = false;
  const mrpt::poses::CPose2D odometry = guess - front_.back();
  const bool every_scan = o_.scan_to_scan_guess_sigma_deg > 0;
  const bool submap = hits && !active_.empty();
  // Only where the submap match fails, unless it sharpens every scan's guess.
  ScanToScanResult s2s{odometry};
  if (every_scan || !submap) s2s = matchPrevious(returns, odometry);
  // The turn only: on the campus log the matched turn is off by 0.13 degrees a step on average
  // where odometry's is off by 0.28, but the matched step by 0.1-0.4 m where odometry's is off
  // by a few centimetres (far returns off trees and bushes pin the heading, not the position).
  const auto turned = [&](double phi) {
    return front_.back() + mrpt::poses::CPose2D(odometry.x(), odometry.y(), phi);
  };
  if (submap) {
    mrpt::poses::CPose2D start = guess;
    if (every_scan && s2s.matched) {  // the two turns averaged by their variances
      const double so2 = std::pow(odometryHeadingSigma(odometry.phi()), 2);
      const double ss2 = std::pow(o_.scan_to_scan_guess_sigma_deg * kDegToRad, 2);
      const double dphi = mrpt::math::wrapToPi(s2s.increment.phi() - odometry.phi());
      start = turned(odometry.phi() + so2 / (so2 + ss2) * dphi);
    }
    const Submap& s = *active_.front();
    const mrpt::poses::CPose2D anchor = front_[s.anchor()];
    const ScanMatchResult r = matcher_.match(*s.map(), rd, start - anchor);
    if (r.matched) {
      ++stats_.matched;
      last_match_ok_ = true;
      last_match_inliers_ = r.inliers;
      return anchor + r.pose;
    }
    ++stats_.fallbacks;
    if (!every_scan) s2s = matchPrevious(returns, odometry);
  }
  if (!s2s.matched) return guess;
  ++stats_.scan_to_scan;
  last_step_matched_ = true;
  return turned(s2s.increment.phi());
}

void Slam::updateSubmaps(const RangeData& rd) {
  const std::size_t i = front_.size() - 1;
  const double path = path_.back();
  const bool start = active_.empty() || path - active_start_.back() >= 0.5 * o_.submap_length_m ||
                     active_.back()->scans() * 2 >= static_cast<std::size_t>(o_.submap_max_scans);
  if (start) {
    active_.push_back(std::make_unique<Submap>(i, map_options_, insertion_));
    active_start_.push_back(path);
    ++stats_.submaps;
  }
  for (auto& s : active_) {
    s->insert(rd, front_[i] - front_[s->anchor()]);
    s->setLastNode(i);
  }
  const bool full = path - active_start_.front() >= o_.submap_length_m ||
                    active_.front()->scans() >= static_cast<std::size_t>(o_.submap_max_scans);
  if (active_.size() >= 2 && full) {
    active_.front()->finish(o_.occupied_threshold, o_.field_sigma_m);
    finished_.push_back(std::move(active_.front()));
    active_.pop_front();
    active_start_.pop_front();
  }
}

void Slam::searchLoops(const std::vector<mrpt::math::TPoint2D>& pts,
                       const std::vector<mrpt::math::TPoint2D>& cloud) {
  const std::size_t i = graph_.size() - 1;
  const double here = path_.back();
  std::vector<std::pair<double, const Submap*>> near;
  for (const auto& s : finished_) {
    if (here - path_[s->lastNode()] < o_.loop_min_path_m || s->field().empty()) continue;
    // Nearest by the submap's middle scan, not its anchor: a scan near the anchor lies at the
    // submap's edge, where the walls behind it were never seen (field value 0), and the search
    // slides it forward into the submap (on corridors_odom every loop edge off by more than
    // 0.1 m had the scan within 0.3 m of the anchor, all along the corridor, all forward).
    const std::size_t middle = (s->anchor() + s->lastNode()) / 2;
    const mrpt::poses::CPose2D rel = graph_.pose(i) - graph_.pose(middle);
    const double d = std::hypot(rel.x(), rel.y());
    if (d <= o_.loop_max_distance_m) near.emplace_back(d, s.get());
  }
  std::sort(near.begin(), near.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second->anchor() < b.second->anchor());
  });
  if (near.size() > static_cast<std::size_t>(o_.loop_max_candidates)) {
    near.resize(static_cast<std::size_t>(o_.loop_max_candidates));
  }
  // The pose is as uncertain as the path since the last loop closure, or since the submap; or,
  // with loop_window_graph, as the path between the two through the graph: a loop closure with
  // a submap just behind says nothing of the error relative to one a building's loop back.
  std::vector<double> apart;
  if (o_.loop_window_graph && !near.empty()) apart = graph_.pathThroughLoops(path_, i);
  bool optimise_now = false;
  for (const auto& [d, s] : near) {
    const double uncertain = o_.loop_window_graph
                                 ? apart[s->anchor()]
                                 : std::min(here - last_closure_path_, here - path_[s->lastNode()]);
    double moved = 0;
    if (tryLoop(*s, pts, cloud, uncertain, moved)) {
      last_closure_path_ = here;
      pending_loops_ = true;
      optimise_now = optimise_now || (o_.loop_optimise_m > 0 && moved > o_.loop_optimise_m);
    }
  }
  if (optimise_now) optimise();
}

double Slam::searchWindow(double uncertain_m, double max_m) const {
  return std::min(max_m, o_.loop_window_m + o_.loop_window_per_m * uncertain_m);
}

bool Slam::searchPlace(const LikelihoodField& field, const std::vector<mrpt::math::TPoint2D>& pts,
                       const mrpt::poses::CPose2D& guess, double uncertain_m, double max_m,
                       double max_deg, std::size_t& proposed, std::size_t& ambiguous,
                       mrpt::poses::CPose2D& found) const {
  const double window = searchWindow(uncertain_m, max_m);
  const double window_deg =
      std::min(max_deg, o_.loop_window_deg + o_.loop_window_deg_per_m * uncertain_m);
  const FieldMatch best =
      searchWide(field, pts, guess, window, window_deg * kDegToRad, o_.angle_step_deg * kDegToRad,
                 o_.loop_ambiguity_m, o_.loop_ambiguity_ratio, o_.loop_min_score);
  if (best.score < o_.loop_min_score) return false;
  ++proposed;
  if (best.runner_up >= o_.loop_ambiguity_ratio * best.score) {
    ++ambiguous;
    return false;
  }
  const FieldMatch fine = refine(field, pts, best.pose, best.pose, 0.0, 0.0, 20);
  if (fine.score < o_.loop_min_score) {
    ++ambiguous;
    return false;
  }
  found = fine.pose;
  return true;
}

bool Slam::tryLoop(const Submap& s, const std::vector<mrpt::math::TPoint2D>& pts,
                   const std::vector<mrpt::math::TPoint2D>& cloud, double uncertain_m,
                   double& moved_m) {
  ++stats_.loop_attempts;
  const std::size_t i = graph_.size() - 1;
  const mrpt::poses::CPose2D guess = graph_.pose(i) - graph_.pose(s.anchor());
  mrpt::poses::CPose2D found;
  const bool wide = o_.loop_cloud_window_m > 0 &&
                    searchWindow(uncertain_m, o_.loop_max_window_m) >= o_.loop_cloud_window_m;
  if (!searchPlace(s.field(), wide ? cloud : pts, guess, uncertain_m, o_.loop_max_window_m,
                   o_.loop_max_window_deg, stats_.loops_proposed, stats_.loops_ambiguous, found)) {
    return false;
  }
  moved_m = std::hypot(found.x() - guess.x(), found.y() - guess.y());
  graph_.addEdge({s.anchor(), i, found,
                  diagonalInformation(o_.loop_sigma_m, o_.loop_sigma_deg * kDegToRad),
                  EdgeKind::LoopClosure});
  return true;
}

void Slam::tieTo(LikelihoodField prior) {
  prior_ = std::make_unique<const LikelihoodField>(std::move(prior));
}

std::vector<mrpt::math::TPoint2D> Slam::recentPoints() const {
  const mrpt::poses::CPose2D here = front_.back();
  std::size_t n = 0;
  for (const auto& r : recent_) n += r.second.size();
  // At most kMaxTiePoints, evenly spaced through the scans: a search's cost grows with them.
  const std::size_t stride = n / kMaxTiePoints + 1;
  std::vector<mrpt::math::TPoint2D> out;
  std::size_t k = 0;
  for (const auto& [j, pts] : recent_) {
    const mrpt::poses::CPose2D rel = front_[j] - here;
    for (const auto& p : pts) {
      if (k++ % stride == 0) out.push_back(rel + p);
    }
  }
  return out;
}

void Slam::tryTie(const std::vector<mrpt::math::TPoint2D>& pts) {
  ++stats_.ties_attempted;
  const std::size_t i = graph_.size() - 1;
  // The graph drifts between optimisations; the last tie says by how much, near here.
  const mrpt::poses::CPose2D guess = prior_offset_ + graph_.pose(i);
  mrpt::poses::CPose2D found;
  if (!searchPlace(*prior_, pts, guess, path_.back() - last_tie_path_, o_.tie_max_window_m,
                   o_.tie_max_window_deg, stats_.ties_proposed, stats_.ties_ambiguous, found)) {
    return;
  }
  last_tie_path_ = path_.back();
  prior_offset_ = found + (mrpt::poses::CPose2D() - graph_.pose(i));
  graph_.addEdge({0, i, found - graph_.pose(0),
                  diagonalInformation(o_.loop_sigma_m, o_.loop_sigma_deg * kDegToRad),
                  EdgeKind::PriorMap});
  pending_loops_ = true;
}

void Slam::optimise() {
  const OptimiseReport r = graph_.optimise(o_.max_iterations, o_.loop_gate, o_.max_rounds);
  ++stats_.optimisations;
  stats_.iterations += r.iterations;
  stats_.converged = r.converged;
  stats_.final_error = r.converged ? r.final_error : r.initial_error;
  nodes_at_last_optimise_ = graph_.size();
  pending_loops_ = false;
  if (r.converged) prior_offset_ = mrpt::poses::CPose2D();  // the graph holds the ties now
}

void Slam::finish() {
  if (pending_loops_ || stats_.optimisations > 0) optimise();
}

std::vector<mrpt::poses::CPose2D> Slam::poses() const {
  if (!stats_.converged) return front_;
  std::vector<mrpt::poses::CPose2D> out;
  out.reserve(graph_.size());
  for (std::size_t i = 0; i < graph_.size(); ++i) out.push_back(graph_.pose(i));
  return out;
}

const SlamStats& Slam::stats() const {
  std::size_t accepted = 0;
  std::size_t ties = 0;
  for (const PoseEdge& e : graph_.edges()) {
    accepted += e.kind == EdgeKind::LoopClosure && e.active;
    ties += e.kind == EdgeKind::PriorMap && e.active;
  }
  stats_.loops_accepted = accepted;
  stats_.ties_accepted = ties;
  stats_.loops_rejected = stats_.loops_proposed - accepted;
  return stats_;
}

}  // namespace dynamap
