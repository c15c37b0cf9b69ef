#include "dynamap/localization/slam.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "dynamap/base/ini.h"
#include "dynamap/localization/field_matcher.h"

namespace dynamap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

/// Every key of [slam], declared once: its member, range and meaning.
struct SlamKey {
  const char* name;
  double SlamOptions::*real;  // one of real / integer is set
  int SlamOptions::*integer;
  double lo, hi;
  bool lo_open;  // (lo, hi] instead of [lo, hi]
  const char* meaning;
};

#define DYNAMAP_REAL(k, lo, hi, open, what) {#k, &SlamOptions::k, nullptr, lo, hi, open, what}
#define DYNAMAP_INT(k, lo, hi, what) {#k, nullptr, &SlamOptions::k, lo, hi, false, what}
const SlamKey kKeys[] = {
    DYNAMAP_REAL(submap_length_m, 0.1, 100, true, "[m] path a submap covers"),
    DYNAMAP_INT(submap_max_scans, 2, 100000, "... or at most this many scans"),
    DYNAMAP_REAL(occupied_threshold, 0.5, 1, true, "submap cells above this P(occ) are walls"),
    DYNAMAP_REAL(field_sigma_m, 0, 1, true, "[m] width of the likelihood field"),
    DYNAMAP_INT(point_stride, 1, 100, "every n-th beam is matched"),
    DYNAMAP_REAL(angle_step_deg, 0, 10, true, "[deg] heading step of every search"),
    DYNAMAP_REAL(odometry_sigma_per_m, 0, 10, true, "odometry edges: translation sd per metre"),
    DYNAMAP_REAL(odometry_sigma_per_rad, 0, 10, true, "odometry edges: heading sd per radian"),
    DYNAMAP_REAL(match_sigma_m, 0, 10, true, "[m] scan-match edges: translation sd"),
    DYNAMAP_REAL(match_sigma_deg, 0, 90, true, "[deg] scan-match edges: heading sd"),
    DYNAMAP_REAL(loop_sigma_m, 0, 10, true, "[m] loop-closure edges: translation sd"),
    DYNAMAP_REAL(loop_sigma_deg, 0, 90, true, "[deg] loop-closure edges: heading sd"),
    DYNAMAP_REAL(loop_every_m, 0, 1000, true, "[m] path between loop closure attempts"),
    DYNAMAP_REAL(loop_min_path_m, 0, 1e6, false, "[m] only submaps this far back along the path"),
    DYNAMAP_REAL(loop_max_distance_m, 0, 1000, true, "[m] ... whose anchor is this close"),
    DYNAMAP_INT(loop_max_candidates, 1, 100, "the nearest n such submaps are searched"),
    DYNAMAP_REAL(loop_window_m, 0, 20, false, "[m] loop search window after a loop closure"),
    DYNAMAP_REAL(loop_window_per_m, 0, 1, false, "... growing by this per metre of path since"),
    DYNAMAP_REAL(loop_max_window_m, 0, 20, false, "[m] ... up to this"),
    DYNAMAP_REAL(loop_window_deg, 0, 180, false, "[deg] heading window after a loop closure"),
    DYNAMAP_REAL(loop_window_deg_per_m, 0, 10, false, "[deg] ... growing by this per metre"),
    DYNAMAP_REAL(loop_max_window_deg, 0, 180, false, "[deg] ... up to this"),
    DYNAMAP_REAL(loop_min_score, 0, 1, false, "a loop closure's points' mean field value"),
    DYNAMAP_REAL(loop_ambiguity_ratio, 0, 1, false, "runner-up / best above this: ambiguous"),
    DYNAMAP_REAL(loop_ambiguity_m, 0, 20, true, "[m] runner-ups this far from the best count"),
    DYNAMAP_INT(optimise_every_nodes, 1, 1000000, "nodes between optimisations (new loops)"),
    DYNAMAP_INT(max_iterations, 1, 10000, "Levenberg-Marquardt iterations per optimisation"),
    DYNAMAP_REAL(loop_gate, 0, 1e9, true, "chi^2 above which a loop closure is rejected"),
    DYNAMAP_INT(max_rounds, 1, 100, "optimise-and-reject rounds per optimisation"),
};
#undef DYNAMAP_REAL
#undef DYNAMAP_INT

Eigen::Matrix3d diagonalInformation(double sigma_xy, double sigma_phi) {
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  info(0, 0) = info(1, 1) = 1.0 / (sigma_xy * sigma_xy);
  info(2, 2) = 1.0 / (sigma_phi * sigma_phi);
  return info;
}

}  // namespace

void SlamOptions::load(const IniFile& ini) {
  std::vector<std::string> names;
  for (const SlamKey& k : kKeys) names.push_back(k.name);
  ini.requireKnownKeys(kSection, names);
  for (const SlamKey& k : kKeys) {
    if (k.real) this->*k.real = ini.getDouble(kSection, k.name, this->*k.real);
    if (k.integer) this->*k.integer = static_cast<int>(ini.getInt(kSection, k.name, this->*k.integer));
  }
  validate(ini.name());
}

void SlamOptions::validate(const std::string& source) const {
  for (const SlamKey& k : kKeys) {
    const double v = k.real ? this->*k.real : this->*k.integer;
    std::ostringstream range;
    range << (k.integer ? "an integer in [" : (k.lo_open ? "in (" : "in [")) << k.lo << ", " << k.hi
          << "]";
    if (k.lo_open && !(v > k.lo)) rejectValue(source, kSection, k.name, "must be " + range.str());
    requireInRange(source, kSection, k.name, v, k.lo, k.hi, range.str());
  }
  if (loop_max_window_m < loop_window_m) {
    rejectValue(source, kSection, "loop_max_window_m", "must be at least loop_window_m");
  }
  if (loop_max_window_deg < loop_window_deg) {
    rejectValue(source, kSection, "loop_max_window_deg", "must be at least loop_window_deg");
  }
}

void SlamOptions::writeIni(std::ostream& out) const {
  out << std::setprecision(10) << "[" << kSection << "]\n";
  for (const SlamKey& k : kKeys) {
    out << k.name << " = ";
    if (k.real) out << this->*k.real; else out << this->*k.integer;
    out << " ; " << k.meaning << "\n";
  }
}

Slam::Slam(const SlamOptions& options, const ScanMatchOptions& matching,
           const DynamicMapOptions& map, const InsertionOptions& insertion)
    : o_(options),
      matcher_(matching, insertion.max_distance_insertion),
      map_options_(map),
      insertion_(insertion),
      max_range_(insertion.max_distance_insertion) {
  o_.validate("slam options");
}

Slam::~Slam() = default;

void Slam::add(const mrpt::poses::CPose2D& odometry,
               const mrpt::obs::CObservation2DRangeScan& scan) {
  // A scan whose mount is not finite is placed by odometry and kept out of the submaps.
  const mrpt::poses::CPose3D& mount = scan.sensorPose;
  const bool usable = std::isfinite(mount.x()) && std::isfinite(mount.y()) &&
                      std::isfinite(mount.z()) && std::isfinite(mount.yaw()) &&
                      std::isfinite(mount.pitch()) && std::isfinite(mount.roll());
  std::vector<mrpt::math::TPoint2D> pts;
  if (usable) pts = scanEndPoints(scan, max_range_, static_cast<std::size_t>(o_.point_stride));
  const std::size_t i = graph_.size();
  ++stats_.scans;
  if (i == 0) {
    front_.push_back(odometry);
    path_.push_back(0);
    graph_.addNode(odometry);
  } else {
    const mrpt::poses::CPose2D inc = odometry - last_odometry_;
    const mrpt::poses::CPose2D pose =
        pts.empty() ? front_.back() + inc : frontEnd(front_.back() + inc, scan);
    const mrpt::poses::CPose2D step = pose - front_.back();
    path_.push_back(path_.back() + std::hypot(step.x(), step.y()));
    front_.push_back(pose);
    graph_.addNode(graph_.pose(i - 1) + step);
    // Odometry: sd grows with the distance and the turn; a floor keeps it invertible.
    const double d = std::hypot(inc.x(), inc.y());
    PoseEdge e{i - 1, i, inc,
               diagonalInformation(0.01 + o_.odometry_sigma_per_m * d,
                                   0.2 * kDegToRad + o_.odometry_sigma_per_rad * std::abs(inc.phi())),
               EdgeKind::Odometry};
    graph_.addEdge(e);
    if (!active_.empty() && active_.front()->anchor() != i && stats_.matched > 0 &&
        last_match_ok_) {
      graph_.addEdge({active_.front()->anchor(), i, pose - front_[active_.front()->anchor()],
                      diagonalInformation(o_.match_sigma_m, o_.match_sigma_deg * kDegToRad),
                      EdgeKind::ScanMatch});
    }
  }
  last_odometry_ = odometry;
  if (!pts.empty()) updateSubmaps(scan);
  if (path_.back() - last_attempt_path_ >= o_.loop_every_m) {
    last_attempt_path_ = path_.back();
    searchLoops(pts);
  }
  if (pending_loops_ && graph_.size() - nodes_at_last_optimise_ >= std::size_t(o_.optimise_every_nodes)) {
    optimise();
  }
}

mrpt::poses::CPose2D Slam::frontEnd(const mrpt::poses::CPose2D& guess,
                                    const mrpt::obs::CObservation2DRangeScan& scan) {
  last_match_ok_ = false;
  if (active_.empty()) return guess;
  const Submap& s = *active_.front();
  const mrpt::poses::CPose2D anchor = front_[s.anchor()];
  const ScanMatchResult r = matcher_.match(*s.map(), scan, guess - anchor);
  if (!r.matched) {
    ++stats_.fallbacks;
    return guess;
  }
  ++stats_.matched;
  last_match_ok_ = true;
  return anchor + r.pose;
}

void Slam::updateSubmaps(const mrpt::obs::CObservation2DRangeScan& scan) {
  const std::size_t i = front_.size() - 1;
  const double path = path_.back();
  const bool start = active_.empty() ||
                     path - active_start_.back() >= 0.5 * o_.submap_length_m ||
                     active_.back()->scans() * 2 >= static_cast<std::size_t>(o_.submap_max_scans);
  if (start) {
    active_.push_back(std::make_unique<Submap>(i, map_options_, insertion_));
    active_start_.push_back(path);
    ++stats_.submaps;
  }
  for (auto& s : active_) {
    s->insert(scan, front_[i] - front_[s->anchor()]);
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

void Slam::searchLoops(const std::vector<mrpt::math::TPoint2D>& pts) {
  const std::size_t i = graph_.size() - 1;
  const double here = path_.back();
  std::vector<std::pair<double, const Submap*>> near;
  for (const auto& s : finished_) {
    if (here - path_[s->lastNode()] < o_.loop_min_path_m || s->field().empty()) continue;
    const mrpt::poses::CPose2D rel = graph_.pose(i) - graph_.pose(s->anchor());
    const double d = std::hypot(rel.x(), rel.y());
    if (d <= o_.loop_max_distance_m) near.emplace_back(d, s.get());
  }
  std::sort(near.begin(), near.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second->anchor() < b.second->anchor());
  });
  if (near.size() > static_cast<std::size_t>(o_.loop_max_candidates)) {
    near.resize(static_cast<std::size_t>(o_.loop_max_candidates));
  }
  for (const auto& [d, s] : near) {
    // The pose is as uncertain as the path since the last loop closure, or since the submap.
    const double uncertain = std::min(here - last_closure_path_, here - path_[s->lastNode()]);
    if (tryLoop(*s, pts, uncertain)) {
      last_closure_path_ = here;
      pending_loops_ = true;
    }
  }
}

bool Slam::tryLoop(const Submap& s, const std::vector<mrpt::math::TPoint2D>& pts,
                   double uncertain_m) {
  ++stats_.loop_attempts;
  const std::size_t i = graph_.size() - 1;
  const mrpt::poses::CPose2D guess = graph_.pose(i) - graph_.pose(s.anchor());
  const double window = std::min(o_.loop_max_window_m, o_.loop_window_m + o_.loop_window_per_m * uncertain_m);
  const double window_deg =
      std::min(o_.loop_max_window_deg, o_.loop_window_deg + o_.loop_window_deg_per_m * uncertain_m);
  const FieldMatch found =
      searchWide(s.field(), pts, guess, window, window_deg * kDegToRad,
                 o_.angle_step_deg * kDegToRad, o_.loop_ambiguity_m, o_.loop_ambiguity_ratio);
  if (found.score < o_.loop_min_score) return false;
  ++stats_.loops_proposed;
  if (found.runner_up >= o_.loop_ambiguity_ratio * found.score) {
    ++stats_.loops_ambiguous;
    return false;
  }
  const FieldMatch fine = refine(s.field(), pts, found.pose, found.pose, 0.0, 0.0, 20);
  if (fine.score < o_.loop_min_score) {
    ++stats_.loops_ambiguous;
    return false;
  }
  graph_.addEdge({s.anchor(), i, fine.pose,
                  diagonalInformation(o_.loop_sigma_m, o_.loop_sigma_deg * kDegToRad),
                  EdgeKind::LoopClosure});
  return true;
}

void Slam::optimise() {
  const OptimiseReport r = graph_.optimise(o_.max_iterations, o_.loop_gate, o_.max_rounds);
  ++stats_.optimisations;
  stats_.iterations += r.iterations;
  stats_.converged = r.converged;
  stats_.final_error = r.converged ? r.final_error : r.initial_error;
  nodes_at_last_optimise_ = graph_.size();
  pending_loops_ = false;
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
  for (const PoseEdge& e : graph_.edges()) accepted += e.kind == EdgeKind::LoopClosure && e.active;
  stats_.loops_accepted = accepted;
  stats_.loops_rejected = stats_.loops_proposed - accepted;
  return stats_;
}

}  // namespace dynamap
