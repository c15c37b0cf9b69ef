#include "dynamap/localization/pose_graph.h"

#include <mrpt/containers/stl_containers_utils.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphs/TNodeID.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <queue>
#include <set>
#include <stdexcept>
#include <string>

// MRPT 2.5's optimize_graph_spa_levmarq maps each edge's two nodes to their index among the free
// nodes with find_in_vector over a std::set: a walk from the set's first node, so every
// optimisation costs edges x nodes tree steps before its first iteration (on Freiburg 079, 4791
// nodes and 9786 edges: 13 % of a whole slam run). The free nodes are every node but the root,
// consecutive ids, so a node's index is its distance from the first id. This specialisation
// gives the same index in O(1) when the set is consecutive, and walks it otherwise, exactly as
// the primary template: the optimisation's arithmetic, and so every pose, is unchanged. It must
// be declared before levmarq.h instantiates the call.
namespace mrpt::containers {
template <>
inline size_t find_in_vector<mrpt::graphs::TNodeID, std::set<mrpt::graphs::TNodeID>>(
    const mrpt::graphs::TNodeID& value, const std::set<mrpt::graphs::TNodeID>& nodes) {
  if (nodes.empty()) return std::string::npos;
  const mrpt::graphs::TNodeID first = *nodes.begin(), last = *nodes.rbegin();
  if (last - first + 1 == nodes.size()) {  // consecutive ids
    return value < first || value > last ? std::string::npos : static_cast<size_t>(value - first);
  }
  const auto it = nodes.find(value);
  return it == nodes.end() ? std::string::npos
                           : static_cast<size_t>(std::distance(nodes.begin(), it));
}
}  // namespace mrpt::containers

#include <mrpt/graphslam/levmarq.h>
#include <mrpt/math/wrap2pi.h>

namespace dynamap {
namespace {

using Graph = mrpt::graphs::CNetworkOfPoses2DInf;

/// The edges the gate may switch off: those of a search that can match the wrong place.
bool gated(const PoseEdge& e) {
  return e.kind == EdgeKind::LoopClosure || e.kind == EdgeKind::PriorMap;
}

Graph toMrpt(const std::vector<mrpt::poses::CPose2D>& poses, const std::vector<PoseEdge>& edges) {
  Graph g;
  g.root = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) g.nodes[i] = poses[i];
  for (const PoseEdge& e : edges) {
    if (!e.active) continue;
    mrpt::poses::CPosePDFGaussianInf z;
    z.mean = e.z;
    z.cov_inv = mrpt::math::CMatrixDouble33(e.information);
    g.insertEdge(e.from, e.to, z);
  }
  return g;
}

bool finite(const mrpt::poses::CPose2D& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi());
}

}  // namespace

std::size_t PoseGraph::addNode(const mrpt::poses::CPose2D& estimate) {
  poses_.push_back(estimate);
  return poses_.size() - 1;
}

void PoseGraph::addEdge(const PoseEdge& edge) {
  if (edge.from >= poses_.size() || edge.to >= poses_.size() || edge.from == edge.to) {
    throw std::out_of_range("pose graph edge between unknown nodes");
  }
  edges_.push_back(edge);
}

std::vector<double> PoseGraph::pathThroughLoops(const std::vector<double>& path,
                                                std::size_t from) const {
  const std::size_t n = poses_.size();
  if (from >= n || path.size() != n) throw std::out_of_range("pathThroughLoops: bad node or path");
  std::vector<std::vector<std::size_t>> jumps(n);
  for (const PoseEdge& e : edges_) {
    if (e.kind != EdgeKind::LoopClosure || !e.active) continue;
    jumps[e.from].push_back(e.to);
    jumps[e.to].push_back(e.from);
  }
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist[from] = 0;
  open.emplace(0.0, from);
  while (!open.empty()) {
    // Not a structured binding: clang (make fuzz) refuses one captured by the lambda below.
    const double d = open.top().first;
    const std::size_t k = open.top().second;
    open.pop();
    if (d > dist[k]) continue;
    auto relax = [&](std::size_t m, double w) {
      if (d + w < dist[m]) dist[m] = d + w, open.emplace(d + w, m);
    };
    if (k > 0) relax(k - 1, std::abs(path[k] - path[k - 1]));
    if (k + 1 < n) relax(k + 1, std::abs(path[k + 1] - path[k]));
    for (std::size_t m : jumps[k]) relax(m, 0.0);
  }
  return dist;
}

double PoseGraph::edgeError(const PoseEdge& e) const {
  const mrpt::poses::CPose2D predicted = poses_[e.to] - poses_[e.from];
  const mrpt::poses::CPose2D d = predicted - e.z;  // e.z^-1 (+) predicted
  const Eigen::Vector3d r(d.x(), d.y(), mrpt::math::wrapToPi(d.phi()));
  return r.dot(e.information * r);
}

bool PoseGraph::solve(int max_iterations, OptimiseReport& report) {
  Graph g = toMrpt(poses_, edges_);
  mrpt::graphslam::TResultInfoSpaLevMarq info{};
  mrpt::containers::yaml params = mrpt::containers::yaml::Map();
  params["max_iterations"] = static_cast<uint64_t>(max_iterations);
  params["verbose"] = false;
  try {
    mrpt::graphslam::optimize_graph_spa_levmarq(g, info, nullptr, params);
  } catch (const std::exception&) {
    return false;
  }
  // num_iters is the index of the last iteration run: every iteration used = no convergence.
  const std::size_t used = info.num_iters + 1;
  report.iterations += used;
  std::vector<mrpt::poses::CPose2D> next(poses_.size());
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    next[i] = g.nodes.at(i);
    if (!finite(next[i])) return false;
  }
  if (!std::isfinite(info.final_total_sq_error) ||
      used >= static_cast<std::size_t>(max_iterations)) {
    return false;
  }
  poses_ = std::move(next);
  return true;
}

OptimiseReport PoseGraph::optimise(int max_iterations, double loop_gate, int max_rounds) {
  OptimiseReport report;
  for (const PoseEdge& e : edges_) {
    if (e.active) report.initial_error += edgeError(e);
  }
  if (poses_.size() < 2) {
    report.converged = true;
    return report;
  }
  const std::vector<mrpt::poses::CPose2D> before = poses_;
  for (int round = 0;; ++round) {
    if (!solve(max_iterations, report)) {
      poses_ = before;
      report.converged = false;
      return report;
    }
    report.converged = true;
    if (round + 1 >= max_rounds) break;  // the last round's result stands
    // A false loop closure drags the poses of true ones too: only those of the gate and at
    // least half the worst residual go in one round.
    double worst = 0;
    for (const PoseEdge& e : edges_) {
      if (e.active && gated(e)) worst = std::max(worst, edgeError(e));
    }
    const double cut = std::max(loop_gate, 0.5 * worst);
    std::size_t rejected = 0;
    for (PoseEdge& e : edges_) {
      if (e.active && gated(e) && worst > loop_gate && edgeError(e) >= cut) {
        e.active = false;
        ++rejected;
      }
    }
    report.rejected += rejected;
    if (rejected == 0) break;
    poses_ = before;  // again from where the rejected edges had not yet pulled the poses
  }
  report.final_error = 0;
  for (const PoseEdge& e : edges_) {
    if (e.active) report.final_error += edgeError(e);
  }
  return report;
}

void PoseGraph::saveG2o(const std::string& path) const {
  const Graph g = toMrpt(poses_, edges_);
  g.saveToTextFile(path);
}

}  // namespace dynamap
