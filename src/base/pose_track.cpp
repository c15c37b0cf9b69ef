#include "dynamap/base/pose_track.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>

namespace dynamap {

void PoseTrack::add(double t, const mrpt::poses::CPose2D& pose) {
  if (samples_.empty() || samples_.back().first <= t) {
    samples_.emplace_back(t, pose);
    return;
  }
  const auto pos = std::upper_bound(samples_.begin(), samples_.end(), t,
                                    [](double v, const auto& s) { return v < s.first; });
  samples_.insert(pos, {t, pose});
}

PoseTrack::Lookup PoseTrack::at(double t, mrpt::poses::CPose2D& pose, bool complete) const {
  if (samples_.empty()) return complete ? Lookup::kMissing : Lookup::kLater;
  const auto& last = samples_.back();
  if (t > last.first) {
    if (!complete) return Lookup::kLater;
    if (t - last.first > kEndTolerance) return Lookup::kMissing;
    pose = last.second;
    return Lookup::kFound;
  }
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), t,
                                      [](const auto& s, double v) { return s.first < v; });
  if (after->first == t) {
    pose = after->second;
    return Lookup::kFound;
  }
  if (after == samples_.begin()) {
    if (after->first - t > kEndTolerance) return Lookup::kMissing;
    pose = after->second;
    return Lookup::kFound;
  }
  const auto& a = *(after - 1);
  const auto& b = *after;
  if (b.first - a.first > kMaxGap) return Lookup::kMissing;
  const double f = (t - a.first) / (b.first - a.first);
  const double dphi = mrpt::math::wrapToPi(b.second.phi() - a.second.phi());
  pose = mrpt::poses::CPose2D(a.second.x() + f * (b.second.x() - a.second.x()),
                              a.second.y() + f * (b.second.y() - a.second.y()),
                              mrpt::math::wrapToPi(a.second.phi() + f * dphi));
  return Lookup::kFound;
}

void PoseTrack::forgetBefore(double t) {
  while (samples_.size() > 1 && samples_[1].first <= t) samples_.pop_front();
}

}  // namespace dynamap
