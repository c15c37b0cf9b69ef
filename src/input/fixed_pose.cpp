#include "dynamap/input/fixed_pose.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "dynamap/base/ini.h"

namespace dynamap {
namespace {

class FixedPoseSource : public ScanSource {
 public:
  FixedPoseSource(std::unique_ptr<ScanSource> inner, const mrpt::poses::CPose2D& pose)
      : inner_(std::move(inner)), pose_(pose) {}

  bool next(ScanRecord& out) override {
    if (!inner_->next(out)) return false;
    out.pose = pose_;
    return true;
  }
  PoseSource poseSource() const override { return PoseSource::Fixed; }
  const SourceStats& stats() const override { return inner_->stats(); }
  const std::string& path() const override { return inner_->path(); }
  double fractionRead() const override { return inner_->fractionRead(); }

 private:
  std::unique_ptr<ScanSource> inner_;
  mrpt::poses::CPose2D pose_;
};

// Every pose moved by the one rigid motion that takes the first scan's pose to `first`.
class StartingAtSource : public ScanSource {
 public:
  StartingAtSource(std::unique_ptr<ScanSource> inner, const mrpt::poses::CPose2D& first)
      : inner_(std::move(inner)), first_(first) {}

  bool next(ScanRecord& out) override {
    if (!inner_->next(out)) return false;
    if (!have_motion_) {
      motion_ = first_ + (-out.pose);  // motion_ + pose = first for the first scan
      have_motion_ = true;
    }
    out.pose = motion_ + out.pose;
    return true;
  }
  PoseSource poseSource() const override { return inner_->poseSource(); }
  const SourceStats& stats() const override { return inner_->stats(); }
  const std::string& path() const override { return inner_->path(); }
  double fractionRead() const override { return inner_->fractionRead(); }
  std::string poseDetail() const override { return inner_->poseDetail(); }

 private:
  std::unique_ptr<ScanSource> inner_;
  mrpt::poses::CPose2D first_, motion_;
  bool have_motion_ = false;
};

}  // namespace

mrpt::poses::CPose2D parseFixedPose(const std::string& text) {
  std::istringstream in(text);
  std::string tok;
  double v[3];
  int n = 0;
  while (in >> tok) {
    if (n == 3) throw std::invalid_argument("'" + text + "': more than three numbers (x y phi)");
    if (!parseDouble(tok, v[n])) {
      throw std::invalid_argument("'" + text + "': '" + tok + "' is not a finite number");
    }
    ++n;
  }
  if (n != 3) throw std::invalid_argument("'" + text + "': expected three numbers, x y phi");
  return mrpt::poses::CPose2D(v[0], v[1], v[2]);
}

std::string formatFixedPose(const mrpt::poses::CPose2D& pose) {
  std::string out;
  for (const double v : {pose.x(), pose.y(), pose.phi()}) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.15g", v);  // shortest form that reads back exactly
    if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
    out += (out.empty() ? "" : " ") + std::string(buf);
  }
  return out;
}

std::unique_ptr<ScanSource> withFixedPose(std::unique_ptr<ScanSource> inner,
                                          const mrpt::poses::CPose2D& pose) {
  return std::make_unique<FixedPoseSource>(std::move(inner), pose);
}

std::unique_ptr<ScanSource> startingAt(std::unique_ptr<ScanSource> inner,
                                       const mrpt::poses::CPose2D& first) {
  return std::make_unique<StartingAtSource>(std::move(inner), first);
}

}  // namespace dynamap
