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
// One place beats another when, of the scans one of them fits clearly better (mean field value
// higher by kClearly), it takes at least kMinWins and a share a fair coin would reach with
// probability below kChance: the difference is the building's, not noise.
constexpr double kClearly = 0.1, kChance = 1e-3;
constexpr int kMinWins = 20;

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

// How well each scan fits the map when followed from `start` (the first scan's pose in it) as
// scan matching would: each from where the one before lay and odometry's step since, searched
// for nearby and refined; where nothing fits, odometry's guess is kept.
std::vector<double> follow(const LikelihoodField& field, const std::vector<FirstScan>& scans,
                           const mrpt::poses::CPose2D& start) {
  std::vector<double> fits(scans.size(), 0.0);
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
    if (r.score >= kMinScore) pose = r.pose;
    fits[n] = r.score;
  }
  return fits;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (const double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// Whether place `a` fits better than `b` beyond chance, scan by scan (a sign test): of the
// scans one of them fits clearly better (by kClearly), `a` must take at least kMinWins, and so
// many that equal places would take as many with probability below kChance.
bool beats(const std::vector<double>& a, const std::vector<double>& b) {
  int wins = 0, losses = 0;
  for (std::size_t n = 0; n < a.size(); ++n) {
    wins += a[n] > b[n] + kClearly;
    losses += b[n] > a[n] + kClearly;
  }
  if (wins < kMinWins) return false;
  // P(at least `wins` of wins + losses fair coin flips), summed in logs.
  const int n = wins + losses;
  double tail = 0;
  for (int k = wins; k <= n; ++k) {
    tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) -
                     n * std::log(2.0));
  }
  return tail < kChance;
}

// The places that fit the first metres almost as well as the best, followed along the log. The
// one that beats every other becomes `g`'s best (true); else false, `g` holding the two places of
// best mean fit. Either way score and runner_up become mean fits along the log.
bool followPlaces(const mrpt::maps::COccupancyGridMap2D& map, const std::vector<FirstScan>& scans,
                  GlobalPlacement& g) {
  const LikelihoodField field =
      LikelihoodField::fromGrid(map, 0.5, std::max(0.05, static_cast<double>(map.getResolution())));
  std::vector<std::pair<mrpt::poses::CPose2D, std::vector<double>>> followed;
  for (const auto& [pose, score] : g.places) {
    if (score >= kAmbiguity * g.places.front().second)
      followed.push_back({pose, follow(field, scans, pose)});
  }
  if (followed.size() < 2) return false;  // the caller asks only when a second place is near
  g.followed_m = scans.back().travel;
  std::stable_sort(followed.begin(), followed.end(), [](const auto& a, const auto& b) {
    return mean(a.second) > mean(b.second);
  });
  for (std::size_t i = 0; i < followed.size(); ++i) {
    bool all = true;
    for (std::size_t j = 0; j < followed.size() && all; ++j)
      all = j == i || beats(followed[i].second, followed[j].second);
    if (!all) continue;
    const std::size_t next = i == 0 ? 1 : 0;  // the best of the others
    g.pose = followed[i].first;
    g.score = mean(followed[i].second);
    g.runner_up_pose = followed[next].first;
    g.runner_up = mean(followed[next].second);
    return true;
  }
  g.pose = followed[0].first;
  g.score = mean(followed[0].second);
  g.runner_up_pose = followed[1].first;
  g.runner_up = mean(followed[1].second);
  return false;
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
  bool told_apart = false;
  if (g.score >= kMinScore && g.runner_up > kAmbiguity * g.score && scans.back().travel > kTravelM)
    told_apart = followPlaces(prior_map, scans, g);
  char what[200];
  std::snprintf(what, sizeof what, "best %s (fit %.2f), next %s (fit %.2f)%s",
                poseText(g.pose).c_str(), g.score, poseText(g.runner_up_pose).c_str(),
                g.runner_up, g.followed_m > 0 ? ", each followed along the log" : "");
  if (g.score < kMinScore) {
    throw InputError(log + ": its first scans fit nowhere in the prior session's map (" + what +
                     "); give --initial-pose \"X Y PHI\"");
  }
  if (!told_apart && g.runner_up > kAmbiguity * g.score) {
    throw InputError(log + ": its first scans fit two places of the prior session's map (" +
                     what + "); give --initial-pose \"X Y PHI\"");
  }
  return g;
}

}  // namespace dynamap
