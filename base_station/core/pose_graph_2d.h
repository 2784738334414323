#pragma once
// SE2 pose graph solved with Ceres, after Ceres' examples/slam/pose_graph_2d: one (x, y, yaw)
// parameter block per node, yaw on an angle manifold, relative-pose residuals weighted by the
// square root of the information matrix, optional robust loss per edge kind, and absolute priors
// that pin a node (e.g. each robot's first keyframe) in the global frame.
// Incremental: nodes and edges can be added between solves; each solve starts from the current
// estimates (warm start). No Ceres headers here.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/se2.h"

namespace cairn::base {

enum class EdgeKind { kOdometry, kLoop, kPrior };
const char* to_string(EdgeKind kind);

/// A relative constraint: the pose of `to` measured in the frame of `from`.
struct PoseGraphEdge {
  KeyframeId from;
  KeyframeId to;
  SE2 T_from_to;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  ///< over (x_m, y_m, yaw_rad)
  EdgeKind kind = EdgeKind::kOdometry;
};

/// An absolute constraint: `node` should sit at T_world_node.
struct PosePrior {
  KeyframeId node;
  SE2 T_world_node;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity() * 1e4;
};

enum class RobustLossType { kNone, kHuber, kCauchy };

struct RobustLossOptions {
  RobustLossType type = RobustLossType::kNone;
  double scale = 1.0;  ///< in units of the whitened residual (sigmas)
};

struct PoseGraphOptions {
  RobustLossOptions odometry_loss{RobustLossType::kNone, 1.0};
  RobustLossOptions loop_loss{RobustLossType::kCauchy, 1.0};
  RobustLossOptions prior_loss{RobustLossType::kNone, 1.0};
};

struct PoseGraphSolveOptions {
  int max_iterations = 100;
  double function_tolerance = 1e-10;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
};

struct PoseGraphSolveResult {
  bool converged = false;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
  std::string reason;
};

class PoseGraph2d {
 public:
  explicit PoseGraph2d(const PoseGraphOptions& options = {});

  /// Adds a node at an initial estimate. False (graph unchanged) if it exists or is not finite.
  bool add_node(KeyframeId id, const SE2& T_world_node);
  /// Overwrites the current estimate of an existing node. False if unknown or not finite.
  bool set_estimate(KeyframeId id, const SE2& T_world_node);
  /// Adds a relative edge. False (graph unchanged) if a node is unknown, from == to, or a value
  /// is not finite. kind must be kOdometry or kLoop.
  bool add_edge(const PoseGraphEdge& edge);
  /// Sets (or replaces) the prior of a node. False if the node is unknown or values not finite.
  bool set_prior(const PosePrior& prior);
  bool remove_prior(KeyframeId id);

  bool has_node(KeyframeId id) const { return nodes_.count(id) > 0; }
  std::optional<SE2> estimate(KeyframeId id) const;
  /// All nodes in (robot, seq) order.
  std::map<KeyframeId, SE2> estimates() const;
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  const std::map<KeyframeId, PosePrior>& priors() const { return priors_; }
  size_t num_nodes() const { return nodes_.size(); }

  /// Solves from the current estimates and stores the result. With no prior the gauge is fixed
  /// by holding the first node constant. An empty graph "converges" trivially.
  PoseGraphSolveResult solve(const PoseGraphSolveOptions& options = {});

 private:
  struct NodeState {
    double x_m = 0, y_m = 0, yaw_rad = 0;
  };
  PoseGraphOptions options_;
  std::map<KeyframeId, NodeState> nodes_;  ///< std::map: stable addresses for Ceres blocks
  std::vector<PoseGraphEdge> edges_;
  std::map<KeyframeId, PosePrior> priors_;
};

}  // namespace cairn::base
