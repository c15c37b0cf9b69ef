#pragma once
// A 2D pose graph and its optimisation by MRPT's sparse Levenberg-Marquardt
// (mrpt::graphslam::optimize_graph_spa_levmarq on a CNetworkOfPoses2DInf).
//
// Edges are odometry, scan-to-submap matches and loop closures. Loop closures are the only
// edges that can be wrong (a symmetric corridor matches itself shifted), so after each
// optimisation the loop closures whose residual exceeds a chi-square gate (and half the worst
// one's: a false closure drags true ones with it) are switched off and the graph is optimised
// again from the poses it had before: a truncated (redescending) loss on loop closures only. An
// optimisation that fails to converge, or gives a pose that is not finite, leaves the poses as they
// were and says so.

#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace dynamap {

/// PriorMap: a scan matched in an earlier session's map, from node 0 (held at the start found
/// there); gated as loop closures are, and like them the only edges that can be wrong.
enum class EdgeKind { Odometry, ScanMatch, LoopClosure, PriorMap };

struct PoseEdge {
  std::size_t from = 0, to = 0;
  mrpt::poses::CPose2D z;  ///< the pose of `to` in the frame of `from`
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  EdgeKind kind = EdgeKind::Odometry;
  bool active = true;  ///< false once rejected by the gate
};

/// What one optimise() did.
struct OptimiseReport {
  bool converged = false;      ///< false: the poses were left as they were
  std::size_t iterations = 0;  ///< Levenberg-Marquardt iterations, over every round
  double initial_error = 0;    ///< sum of squared Mahalanobis residuals before
  double final_error = 0;      ///< ... and after (of the active edges)
  std::size_t rejected = 0;    ///< loop closures switched off by this call
};

class PoseGraph {
 public:
  /// Adds a node with an initial estimate; returns its id (0, 1, ...). Node 0 is held fixed.
  std::size_t addNode(const mrpt::poses::CPose2D& estimate);
  /// Adds an edge between existing nodes; throws std::out_of_range otherwise.
  void addEdge(const PoseEdge& edge);

  /// Optimises every node but 0, then gates loop closures (residual chi^2 > `loop_gate` and at
  /// least half the worst one's) and optimises again without them, at most `max_rounds` runs.
  OptimiseReport optimise(int max_iterations, double loop_gate, int max_rounds);

  std::size_t size() const { return poses_.size(); }
  const mrpt::poses::CPose2D& pose(std::size_t node) const { return poses_.at(node); }
  void setPose(std::size_t node, const mrpt::poses::CPose2D& p) { poses_.at(node) = p; }
  const std::vector<PoseEdge>& edges() const { return edges_; }
  /// The path between node `from` and every node through the graph (Dijkstra): along the chain
  /// of nodes, node k and k+1 `path[k + 1] - path[k]` apart (path: the path length at each node,
  /// non-decreasing, one per node), and 0 across an active loop closure. How far apart two
  /// nodes are for the error of their relative pose. Throws std::out_of_range on a bad `from`
  /// or a `path` of the wrong size.
  std::vector<double> pathThroughLoops(const std::vector<double>& path, std::size_t from) const;
  /// chi^2 of one edge at the current poses.
  double edgeError(const PoseEdge& e) const;

  /// Writes the graph (active edges) with MRPT's CNetworkOfPoses2DInf::saveToTextFile: VERTEX_SE2 /
  /// EDGE_SE2 lines (g2o's format, read by g2o and MRPT's graph tools). Throws on I/O errors.
  void saveG2o(const std::string& path) const;

 private:
  /// One Levenberg-Marquardt run over the active edges; false if it failed.
  bool solve(int max_iterations, OptimiseReport& report);

  std::vector<mrpt::poses::CPose2D> poses_;
  std::vector<PoseEdge> edges_;
};

}  // namespace dynamap
