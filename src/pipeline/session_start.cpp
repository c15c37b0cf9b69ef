#include "dynamap/pipeline/session_start.h"

#include <cmath>
#include <cstdio>

#include "dynamap/localization/likelihood_field.h"

namespace dynamap {
namespace {

constexpr double kTravelM = 4.0, kHeadM = 1.0;  // [m] of path: the cloud, its head
constexpr std::size_t kMaxScans = 100;
constexpr double kMinScore = 0.35, kAmbiguity = 0.9;

std::string poseText(const mrpt::poses::CPose2D& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.2f %.2f %.3f", p.x(), p.y(), p.phi());
  return buf;
}

// The hit points of the first scans, in the first scan's robot frame; those of the first kHeadM
// of path also into `head`.
std::vector<mrpt::math::TPoint2D> firstScans(ScanSource& source, const InsertionOptions& insertion,
                                             std::vector<mrpt::math::TPoint2D>& head) {
  std::vector<mrpt::math::TPoint2D> pts;
  ScanRecord rec;
  RangeData rd;
  mrpt::poses::CPose2D first, last;
  double travel = 0;
  for (std::size_t n = 0; n < kMaxScans && travel <= kTravelM && source.next(rec); ++n) {
    if (n == 0) first = last = rec.pose;
    travel += std::hypot(rec.pose.x() - last.x(), rec.pose.y() - last.y());
    last = rec.pose;
    insertion.rangeData(*rec.scan, rd);
    const mrpt::poses::CPose2D rel = rec.pose - first;  // this scan in the first one's frame
    for (const auto& p : hitPoints(rd)) {
      pts.push_back(rel + p);
      if (travel <= kHeadM) head.push_back(pts.back());
    }
  }
  return pts;
}

}  // namespace

GlobalPlacement locateStart(ScanSource& source, const mrpt::maps::COccupancyGridMap2D& prior_map,
                            const InsertionOptions& insertion, const std::string& log) {
  std::vector<mrpt::math::TPoint2D> head;
  const std::vector<mrpt::math::TPoint2D> pts = firstScans(source, insertion, head);
  const GlobalPlacement g = placeInMap(prior_map, pts, head);
  char what[160];
  std::snprintf(what, sizeof what, "best %s (fit %.2f), next %s (fit %.2f)",
                poseText(g.pose).c_str(), g.score, poseText(g.runner_up_pose).c_str(),
                g.runner_up);
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
