#pragma once
// A 2D tf tree of a bag: each child frame's pose in its parent, static or a timed track, and
// the conversions of ROS transforms into MRPT poses. Private to the bag reader (bag_source.cpp).

#include <geometry_msgs/Quaternion.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "dynamap/base/pose_track.h"

namespace dynamap::bag {

constexpr std::size_t kMaxFrames = 1000;  // distinct child frames in the tf tree
constexpr std::size_t kMaxChain = 64;     // frames between a frame and its tree's root

/// tf frame names with and without tf1's leading slash are the same frame.
std::string frameName(const std::string& f);

/// The yaw of a rotation; NaN when the quaternion is not finite or far from unit length.
double yawOf(const geometry_msgs::Quaternion& q);

/// (x, y, the rotation's yaw) as a pose; none when any is not finite.
std::optional<mrpt::poses::CPose2D> pose2D(double x, double y, const geometry_msgs::Quaternion& q);

/// A 2D tf tree: each child frame's pose in its parent, static or a timed track.
class TfTree {
 public:
  using Lookup = PoseTrack::Lookup;

  /// False (the transform is dropped) when it would add a frame past kMaxFrames.
  bool add(const std::string& parent, const std::string& child, double t,
           const mrpt::poses::CPose2D& pose, bool is_static) {
    auto it = edges_.find(child);
    if (it == edges_.end()) {
      if (edges_.size() >= kMaxFrames) return false;
      it = edges_.emplace(child, Edge{}).first;
    }
    Edge& e = it->second;
    if (e.parent != parent) e.track = PoseTrack();  // re-parented: the old samples are moot
    e.parent = parent;
    e.is_static = is_static;
    if (is_static)
      e.fixed = pose;
    else
      e.track.add(t, pose);
    return true;
  }

  bool knows(const std::string& frame) const {
    if (edges_.count(frame)) return true;
    for (const auto& kv : edges_) {
      if (kv.second.parent == frame) return true;
    }
    return false;
  }

  /// The pose of `source` in `target` at time t (kLater: a later transform may still make it
  /// known; with `complete` none will).
  Lookup lookup(const std::string& target, const std::string& source, double t, bool complete,
                mrpt::poses::CPose2D& out) const {
    const std::vector<std::string> up_s = chain(source), up_t = chain(target);
    const auto common = std::find_first_of(up_s.begin(), up_s.end(), up_t.begin(), up_t.end());
    // Frames not (yet) connected: a transform joining them may still come.
    if (common == up_s.end()) return complete ? Lookup::kMissing : Lookup::kLater;
    mrpt::poses::CPose2D in_common_s, in_common_t;
    const Lookup a = poseIn(source, *common, t, complete, in_common_s);
    if (a != Lookup::kFound) return a;
    const Lookup b = poseIn(target, *common, t, complete, in_common_t);
    if (b != Lookup::kFound) return b;
    // Composing with an identity is not exact in MRPT (p + 0 moves phi by ~1e-13): a pose in
    // the target frame itself, the usual case, is taken as it is.
    out = *common == target ? in_common_s : in_common_s - in_common_t;
    return Lookup::kFound;
  }

  std::size_t samples() const {
    std::size_t n = 0;
    for (const auto& kv : edges_) n += kv.second.track.size();
    return n;
  }

  /// Forgets timed samples no lookup at time >= t needs.
  void forgetBefore(double t) {
    for (auto& kv : edges_) kv.second.track.forgetBefore(t);
  }

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
    mrpt::poses::CPose2D fixed;
    PoseTrack track;
  };

  /// `frame`, its parent, ... up to its root (bounded: a cycle in a corrupt bag ends it).
  std::vector<std::string> chain(const std::string& frame) const {
    std::vector<std::string> out{frame};
    for (auto it = edges_.find(frame); it != edges_.end() && out.size() < kMaxChain;
         it = edges_.find(out.back())) {
      if (std::find(out.begin(), out.end(), it->second.parent) != out.end()) break;
      out.push_back(it->second.parent);
    }
    return out;
  }

  /// The pose of `frame` in its ancestor `ancestor`, composed edge by edge.
  Lookup poseIn(const std::string& frame, const std::string& ancestor, double t, bool complete,
                mrpt::poses::CPose2D& out) const {
    out = mrpt::poses::CPose2D();
    for (std::string f = frame; f != ancestor;) {
      const Edge& e = edges_.at(f);
      mrpt::poses::CPose2D p = e.fixed;
      if (!e.is_static) {
        const Lookup r = e.track.at(t, p, complete);
        if (r != Lookup::kFound) return r;
      }
      out = f == frame ? p : p + out;  // the first edge as it is (see lookup)
      f = e.parent;
    }
    return Lookup::kFound;
  }

  std::map<std::string, Edge> edges_;  // by child frame
};

}  // namespace dynamap::bag
