#include "dynamap/base/pose_track.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>

namespace dynamap {

void PoseTrack::add(double t, const mrpt::poses::CPose2D& pose) {
  ++added_;
  if (samples_.empty() || samples_.back().first <= t) {
    if (!samples_.empty() && spacing_.size() < kSpacingSamples && t > samples_.back().first) {
      spacing_.push_back(t - samples_.back().first);
      median_gap_ = -1;
    }
    samples_.emplace_back(t, pose);
    return;
  }
  const auto pos = std::upper_bound(samples_.begin(), samples_.end(), t,
                                    [](double v, const auto& s) { return v < s.first; });
  samples_.insert(pos, {t, pose});
}

double PoseTrack::maxGap() const {
  if (options_.max_gap > 0) return options_.max_gap;
  if (spacing_.empty()) return kMinAutoGap;
  if (median_gap_ < 0) {
    std::vector<double> s = spacing_;
    const auto mid = s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2);
    std::nth_element(s.begin(), mid, s.end());
    median_gap_ = *mid;
  }
  return std::max(kMinAutoGap, kAutoGapFactor * median_gap_);
}

PoseTrack::Iter PoseTrack::match(double t) const {
  const double tol = options_.match_tolerance;
  auto it = std::lower_bound(samples_.begin(), samples_.end(), t - tol,
                             [](const auto& s, double v) { return s.first < v; });
  Iter best = samples_.end();
  for (; it != samples_.end() && it->first <= t + tol; ++it) {
    if (best == samples_.end() || std::abs(it->first - t) < std::abs(best->first - t)) best = it;
  }
  return best;
}

bool PoseTrack::sharedTime(Iter s) const {
  const auto differs = [&](Iter o) { return o->first == s->first && !(o->second == s->second); };
  return (s != samples_.begin() && differs(s - 1)) || (s + 1 != samples_.end() && differs(s + 1));
}

PoseTrack::Lookup PoseTrack::at(double t, mrpt::poses::CPose2D& pose, bool complete) const {
  if (samples_.empty()) return complete ? Lookup::kMissing : Lookup::kLater;
  if (const Iter m = match(t); m != samples_.end()) {
    if (options_.shared_time_ambiguous && sharedTime(m)) return Lookup::kAmbiguous;
    pose = m->second;
    return Lookup::kFound;
  }
  const auto& last = samples_.back();
  if (t > last.first) {
    if (!complete) return Lookup::kLater;
    if (t - last.first > options_.end_tolerance) return Lookup::kMissing;
    pose = last.second;
    return Lookup::kFound;
  }
  const auto after = std::lower_bound(samples_.begin(), samples_.end(), t,
                                      [](const auto& s, double v) { return s.first < v; });
  if (after == samples_.begin()) {
    if (after->first - t > options_.end_tolerance) return Lookup::kMissing;
    pose = after->second;
    return Lookup::kFound;
  }
  const auto& a = *(after - 1);
  const auto& b = *after;
  if (b.first - a.first > maxGap()) return Lookup::kMissing;
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
