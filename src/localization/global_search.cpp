#include "dynamap/localization/global_search.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <mrpt/math/wrap2pi.h>

#include "dynamap/localization/field_matcher.h"
#include "dynamap/localization/likelihood_field.h"

namespace dynamap {
namespace {

constexpr double kCoarseMinRes = 0.2;  // [m] coarse cells at least this wide...
constexpr int kCoarseMaxSide = 640;     // ...and at most this many on a side
constexpr double kCoarseStep = 1.5 * M_PI / 180.0;
constexpr double kFineStep = 0.25 * M_PI / 180.0;
constexpr std::size_t kMaxPoints = 400;
// Two places are one within these (searchWide's own separation of a runner-up: 1 m, 5 degrees).
constexpr double kSeparationM = 1.0, kSeparationRad = 5.0 * M_PI / 180.0;
constexpr std::size_t kMaxPlaces = 8;  // places the coarse search offers (a hall's symmetries)

// A copy of `map` with cells `factor` times wider: occupied where any of its cells is, free where
// every observed one is free, unknown where none was observed.
mrpt::maps::COccupancyGridMap2D coarsen(const mrpt::maps::COccupancyGridMap2D& map, int factor) {
  const double res = map.getResolution() * factor;
  mrpt::maps::COccupancyGridMap2D c(map.getXMin(), map.getXMax() + static_cast<float>(res),
                                    map.getYMin(), map.getYMax() + static_cast<float>(res),
                                    static_cast<float>(res));
  const int cw = static_cast<int>(c.getSizeX()), ch = static_cast<int>(c.getSizeY());
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(cw) * ch, 0);  // 1 free, 2 occupied
  const auto& raw = map.getRawMap();
  const int sx = static_cast<int>(map.getSizeX()), sy = static_cast<int>(map.getSizeY());
  for (int y = 0; y < sy; ++y) {
    for (int x = 0; x < sx; ++x) {
      const auto v = raw[static_cast<std::size_t>(y) * sx + x];
      const int cx = c.x2idx(map.idx2x(x)), cy = c.y2idx(map.idx2y(y));
      if (v == 0 || cx < 0 || cy < 0 || cx >= cw || cy >= ch) continue;  // never observed
      auto& k = seen[static_cast<std::size_t>(cy) * cw + cx];
      k = std::max<std::uint8_t>(k, v < 0 ? 2 : 1);  // v < 0: P(free) below 0.5
    }
  }
  for (int cy = 0; cy < ch; ++cy) {
    for (int cx = 0; cx < cw; ++cx) {
      const auto k = seen[static_cast<std::size_t>(cy) * cw + cx];
      if (k) c.setCell(cx, cy, k == 2 ? 0.05f : 0.95f);
    }
  }
  return c;
}

// At most kMaxPoints of `all`, evenly.
std::vector<mrpt::math::TPoint2D> subsample(const std::vector<mrpt::math::TPoint2D>& all) {
  std::vector<mrpt::math::TPoint2D> pts;
  const std::size_t stride = std::max<std::size_t>(1, (all.size() + kMaxPoints - 1) / kMaxPoints);
  for (std::size_t i = 0; i < all.size(); i += stride) pts.push_back(all[i]);
  return pts;
}

}  // namespace

GlobalPlacement placeInMap(const mrpt::maps::COccupancyGridMap2D& map,
                           const std::vector<mrpt::math::TPoint2D>& all,
                           const std::vector<mrpt::math::TPoint2D>& head) {
  GlobalPlacement out;
  const std::vector<mrpt::math::TPoint2D> pts = subsample(all);
  if (pts.empty() || map.getSizeX() == 0) return out;
  const double res = map.getResolution();
  const double side = std::max(map.getXMax() - map.getXMin(), map.getYMax() - map.getYMin());
  const int factor = std::max({1, static_cast<int>(std::ceil(kCoarseMinRes / res - 1e-9)),
                               static_cast<int>(std::ceil(side / res / kCoarseMaxSide))});
  const auto coarse_map = coarsen(map, factor);
  const double cres = coarse_map.getResolution();
  const LikelihoodField coarse = LikelihoodField::fromGrid(coarse_map, 0.5, cres);
  if (coarse.empty()) return out;
  const mrpt::poses::CPose2D centre(0.5 * (map.getXMin() + map.getXMax()),
                                    0.5 * (map.getYMin() + map.getYMax()), 0.0);
  const std::vector<FieldMatch> coarse_places = searchPlaces(
      coarse, pts, centre, 0.5 * side + cres, M_PI, kCoarseStep, kSeparationM, 0.9, kMaxPlaces);
  if (coarse_places.empty()) return out;
  const FieldMatch& c = coarse_places.front();
  out.coarse_score = c.score;
  // The map's own resolution, within a coarse cell and step of each answer: the coarse field
  // blurs what tells two similar places apart, the fine one keeps it.
  const LikelihoodField fine = LikelihoodField::fromGrid(map, 0.5, std::max(res, 0.05));
  const auto sharpen = [&](const mrpt::poses::CPose2D& at) {
    const FieldMatch f = searchWide(fine, pts, at, cres, kCoarseStep, kFineStep, 1.0, 1.0);
    return refine(fine, pts, f.pose, f.pose, 0, 0, 30);
  };
  const FieldMatch best = sharpen(c.pose);
  out.pose = best.pose;
  out.score = best.score;
  if (!head.empty()) {  // the pose of the head alone, free of the rest's odometry error
    const std::vector<mrpt::math::TPoint2D> few = subsample(head);
    const FieldMatch f = searchWide(fine, few, best.pose, 0.3, 3 * M_PI / 180, kFineStep, 1.0, 1.0);
    out.pose = refine(fine, few, f.pose, f.pose, 0, 0, 30).pose;
  }
  out.places.push_back({out.pose, out.score});
  for (std::size_t k = 1; k < coarse_places.size(); ++k) {
    const FieldMatch next = sharpen(coarse_places[k].pose);
    // Sharpened onto a place already found, it was that place's blur, not another place.
    const bool same = std::any_of(out.places.begin(), out.places.end(), [&](const auto& p) {
      return std::hypot(next.pose.x() - p.first.x(), next.pose.y() - p.first.y()) < kSeparationM &&
             std::abs(mrpt::math::wrapToPi(next.pose.phi() - p.first.phi())) < kSeparationRad;
    });
    if (same) continue;
    if (out.places.size() == 1) {  // the coarse search's runner-up
      out.runner_up = next.score;
      out.runner_up_pose = next.pose;
    }
    out.places.push_back({next.pose, next.score});
  }
  return out;
}

}  // namespace dynamap
