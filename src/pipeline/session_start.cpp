#include "dynamap/pipeline/session_start.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynamap/localization/field_matcher.h"
#include "dynamap/localization/likelihood_field.h"

namespace dynamap {
namespace {

constexpr double kTravelM = 4.0, kHeadM = 1.0;  // [m] of path: the cloud, its head
constexpr std::size_t kMaxScans = 100;
constexpr double kMinScore = 0.35, kAmbiguity = 0.9;
// Places that fit the first metres alike are followed this far (at most this many scans, every
// kFollowStride-th hit) to tell them apart, each scan searched for this near where the one
// before and odometry's step put it.
constexpr double kFollowM = 25.0;
constexpr std::size_t kFollowScans = 500, kFollowStride = 4;
constexpr double kFollowWindowM = 0.25, kFollowWindowRad = 3.0 * M_PI / 180.0;
constexpr double kFollowStepRad = 0.5 * M_PI / 180.0;

std::string poseText(const mrpt::poses::CPose2D& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.2f %.2f %.3f", p.x(), p.y(), p.phi());
  return buf;
}

// One scan of the log's first metres: its pose in the log's frame, the path up to it, its hits
// in its own robot frame.
struct FirstScan {
  mrpt::poses::CPose2D pose;
  double travel = 0;
  std::vector<mrpt::math::TPoint2D> hits;
};

std::vector<FirstScan> readFirst(ScanSource& source, const InsertionOptions& insertion) {
  std::vector<FirstScan> scans;
  ScanRecord rec;
  RangeData rd;
  double travel = 0;
  while (scans.size() < kFollowScans && travel <= kFollowM && source.next(rec)) {
    if (!scans.empty()) {
      travel += std::hypot(rec.pose.x() - scans.back().pose.x(),
                           rec.pose.y() - scans.back().pose.y());
    }
    insertion.rangeData(*rec.scan, rd);
    scans.push_back({rec.pose, travel, hitPoints(rd)});
  }
  return scans;
}

// The hit points of the scans over the first kTravelM of path (at most kMaxScans), in the first
// scan's robot frame; those of the first kHeadM of path also into `head`.
std::vector<mrpt::math::TPoint2D> cloudOf(const std::vector<FirstScan>& scans,
                                          std::vector<mrpt::math::TPoint2D>& head) {
  std::vector<mrpt::math::TPoint2D> pts;
  for (std::size_t n = 0; n < scans.size() && n < kMaxScans; ++n) {
    if (n > 0 && scans[n - 1].travel > kTravelM) break;
    const mrpt::poses::CPose2D rel = scans[n].pose - scans[0].pose;  // in the first one's frame
    for (const auto& p : scans[n].hits) {
      pts.push_back(rel + p);
      if (scans[n].travel <= kHeadM) head.push_back(pts.back());
    }
  }
  return pts;
}

// How well the scans keep fitting the map when followed from `start` (the first scan's pose in
// it) as scan matching would: each from where the one before lay and odometry's step since,
// searched for nearby and refined. The mean fit over the scans.
double follow(const LikelihoodField& field, const std::vector<FirstScan>& scans,
              const mrpt::poses::CPose2D& start) {
  double sum = 0;
  mrpt::poses::CPose2D pose = start;
  std::vector<mrpt::math::TPoint2D> pts;
  for (std::size_t n = 0; n < scans.size(); ++n) {
    if (n > 0) pose = pose + (scans[n].pose - scans[n - 1].pose);
    pts.clear();
    for (std::size_t k = 0; k < scans[n].hits.size(); k += kFollowStride)
      pts.push_back(scans[n].hits[k]);
    if (pts.empty()) continue;
    const FieldMatch f =
        searchWide(field, pts, pose, kFollowWindowM, kFollowWindowRad, kFollowStepRad, 1.0, 1.0);
    const FieldMatch r = refine(field, pts, f.pose, f.pose, 0, 0, 10);
    pose = r.pose;
    sum += r.score;
  }
  return scans.empty() ? 0.0 : sum / static_cast<double>(scans.size());
}

// The places that fit the first metres almost as well as the best, followed along the log: the
// best and the runner-up of `g` become the two that fit it best there.
void followPlaces(const mrpt::maps::COccupancyGridMap2D& map, const std::vector<FirstScan>& scans,
                  GlobalPlacement& g) {
  const LikelihoodField field =
      LikelihoodField::fromGrid(map, 0.5, std::max(0.05, static_cast<double>(map.getResolution())));
  std::vector<std::pair<double, mrpt::poses::CPose2D>> fits;  // (mean fit, start)
  for (const auto& [pose, score] : g.places) {
    if (score >= kAmbiguity * g.places.front().second) fits.push_back({follow(field, scans, pose), pose});
  }
  std::stable_sort(fits.begin(), fits.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  g.pose = fits[0].second;
  g.score = fits[0].first;
  g.runner_up_pose = fits[1].second;
  g.runner_up = fits[1].first;
  g.followed_m = scans.back().travel;
}

}  // namespace

GlobalPlacement locateStart(ScanSource& source, const mrpt::maps::COccupancyGridMap2D& prior_map,
                            const InsertionOptions& insertion, const std::string& log) {
  const std::vector<FirstScan> scans = readFirst(source, insertion);
  std::vector<mrpt::math::TPoint2D> head;
  const std::vector<mrpt::math::TPoint2D> pts = cloudOf(scans, head);
  GlobalPlacement g = placeInMap(prior_map, pts, head);
  // Several places fit the first metres (a symmetric building): the wrong ones stop fitting
  // where the building's parts differ.
  if (g.score >= kMinScore && g.runner_up > kAmbiguity * g.score && scans.back().travel > kTravelM)
    followPlaces(prior_map, scans, g);
  char what[200];
  std::snprintf(what, sizeof what, "best %s (fit %.2f), next %s (fit %.2f)%s",
                poseText(g.pose).c_str(), g.score, poseText(g.runner_up_pose).c_str(),
                g.runner_up, g.followed_m > 0 ? ", each followed along the log" : "");
  if (g.score < kMinScore) {
    throw InputError(log + ": its first scans fit nowhere in the prior session's map (" + what +
                     "); give --initial-pose \"X Y PHI\"");
  }
  if (g.runner_up > kAmbiguity * g.score) {
    throw InputError(log + ": its first scans fit two places of the prior session's map (" +
                     what + "); give --initial-pose \"X Y PHI\"");
  }
  return g;
}

}  // namespace dynamap
