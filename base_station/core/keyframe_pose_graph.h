#pragma once
// SE2 pose graph solved with Ceres, after Ceres' examples/slam/pose_graph_2d: one (x, y, yaw)
// parameter block per node, yaw on an angle manifold, relative-pose residuals weighted by the
// square root of the information matrix, optional robust loss per edge kind, and absolute priors
// that pin a node (e.g. each robot's first keyframe) in the global frame.
// Incremental: the Ceres problem stays alive between solves; new nodes, edges and priors are added
// as residual blocks and each solve starts from the current estimates (warm start), so an update
// costs a bounded number of iterations. One 3-vector (x, y, yaw) parameter block per node with
// yaw wrapped by a manifold. No Ceres headers here.
#include <Eigen/Core>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "common/ids.h"
#include "common/landmark_observation.h"
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

/// Where one robot was when another saw it (MapperData::sightings[index]; sightings.h).
struct SightingNodeId {
  int32_t index = -1;
  friend constexpr bool operator==(SightingNodeId a, SightingNodeId b) { return a.index == b.index; }
  friend constexpr bool operator!=(SightingNodeId a, SightingNodeId b) { return a.index != b.index; }
  friend constexpr bool operator<(SightingNodeId a, SightingNodeId b) { return a.index < b.index; }
};

/// A 2D point node of the graph: an identified marker, a merged object of interest (named by its
/// cluster's id, the smallest ObjectId of its reports), or a robot where a teammate saw it.
/// Distinct types: a marker and an object never share a node whatever their numbers.
using PointNodeId = std::variant<LandmarkId, ObjectId, SightingNodeId>;
std::string to_string(const PointNodeId& id);

/// A range-bearing observation of point node `landmark` (a marker or an object) from pose node `from`.
struct LandmarkEdge {
  KeyframeId from;
  PointNodeId landmark;
  double range_m = 0.0;
  double bearing_rad = 0.0;
  double sigma_range_m = 0.05;
  double sigma_bearing_rad = 0.02;
};

enum class RobustLossType { kNone, kHuber, kCauchy };

struct RobustLossOptions {
  RobustLossType type = RobustLossType::kNone;
  double scale = 1.0;  ///< in units of the whitened residual (sigmas)
};

/// kRelativePose: Ceres' pose_graph_2d error, weighted by the full information matrix.
/// kSeSync: SE-Sync's objective per edge (kappa ||R_j - R_i R_ij||_F^2 + tau ||t_j - t_i - R_i t_ij||^2),
/// to polish a solution for comparison with certified optima.
enum class EdgeResidualType { kRelativePose, kSeSync };

struct KeyframePoseGraphOptions {
  EdgeResidualType residual = EdgeResidualType::kRelativePose;
  RobustLossOptions odometry_loss{RobustLossType::kNone, 1.0};
  RobustLossOptions loop_loss{RobustLossType::kCauchy, 1.0};
  RobustLossOptions prior_loss{RobustLossType::kNone, 1.0};
  /// Range-bearing landmark (and sighting) residuals: a wrongly identified marker must not bend the map.
  RobustLossOptions landmark_loss{RobustLossType::kCauchy, 2.0};
  /// Observations of merged objects (multi_robot_mapper_objects.cpp): a wrong merge must not bend it.
  RobustLossOptions object_loss{RobustLossType::kCauchy, 1.0};
};

struct PoseGraphSolveOptions {
  int max_iterations = 100;
  double function_tolerance = 1e-10;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
  /// Stop after this much solver time (0: no limit); the next warm-started solve continues.
  double max_time_s = 0.0;
  /// Only these nodes (and the landmarks they observe) move when non-empty: a bounded local
  /// update. It solves a problem built from their residual blocks only (every other node they
  /// touch held constant), so it costs O(window), not O(graph).
  std::vector<KeyframeId> active_nodes;
  /// Sparse Cholesky of the normal equations by Eigen's simplicial LDLT (true) or SuiteSparse
  /// CHOLMOD (false). Debian's CHOLMOD enters an OpenMP region per supernode with 4 threads on any
  /// machine (OMP_NUM_THREADS is not honoured): ~27,000 futex calls per factorisation of the 10,000-
  /// keyframe live graph, at microseconds each in these VMs. Eigen: the same solution, 10 iterations
  /// 0.58-0.64 s CPU against 1.0-1.7 s there, and no slower on the SE-Sync benchmark graphs
  /// (docs/benchmarks.md).
  bool eigen_sparse = true;
};

struct PoseGraphSolveResult {
  bool converged = false;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
  int variable_blocks = 0;  ///< parameter blocks of the solved problem that could move
  std::string reason;
};

class KeyframePoseGraph {
 public:
  explicit KeyframePoseGraph(const KeyframePoseGraphOptions& options = {});
  ~KeyframePoseGraph();
  /// Copies carry the graph and estimates; the copy builds its own Ceres problem on first solve.
  KeyframePoseGraph(const KeyframePoseGraph& other);
  KeyframePoseGraph& operator=(const KeyframePoseGraph& other);
  KeyframePoseGraph(KeyframePoseGraph&&) noexcept;
  KeyframePoseGraph& operator=(KeyframePoseGraph&&) noexcept;

  /// Adds a node at an initial estimate. False (graph unchanged) if it exists or is not finite.
  bool add_node(KeyframeId id, const SE2& T_world_node);
  /// Overwrites the current estimate of an existing node. False if unknown or not finite.
  bool set_estimate(KeyframeId id, const SE2& T_world_node);
  /// Adds a relative edge. False (graph unchanged) if a node is unknown, from == to, or a value
  /// is not finite. kind must be kOdometry or kLoop.
  bool add_edge(const PoseGraphEdge& edge);
  /// Replaces the measurement of edge `index` (of edges()), also in the live Ceres problem (no
  /// rebuild): a robot's chain re-measured by its agent's loop closing. False (unchanged) if out of
  /// range or a value is not finite / not positive definite.
  bool set_edge_measurement(size_t index, const SE2& T_from_to, const Eigen::Matrix3d& information);
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
  /// Replaces every estimate (e.g. by a LAGO initialisation); unknown ids are ignored.
  void set_estimates(const std::map<KeyframeId, SE2>& estimates);

  // Landmarks (keyframe_pose_graph_landmarks.cpp): 2D point nodes (markers and objects) with range-bearing
  // residuals (robust loss landmark_loss / object_loss). A node is created by its first observation.
  /// Adds an observation. False (graph unchanged) if the pose node is unknown or a value is not
  /// finite / a sigma not positive / the range below 1 cm.
  bool add_landmark_edge(const LandmarkEdge& edge);
  /// Whether any landmark observation from `node` is in the graph.
  bool has_landmark_edges_from(KeyframeId node) const { return landmark_sources_.count(node) > 0; }
  std::optional<Eigen::Vector2d> landmark_estimate(LandmarkId id) const { return point_estimate(id); }
  std::optional<Eigen::Vector2d> point_estimate(const PointNodeId& id) const;
  /// Marker nodes only.
  std::map<LandmarkId, Eigen::Vector2d> landmark_estimates() const;
  /// Object nodes only.
  std::map<ObjectId, Eigen::Vector2d> object_estimates() const;
  /// Every point node (markers first, then objects).
  std::map<PointNodeId, Eigen::Vector2d> point_estimates() const;
  const std::vector<LandmarkEdge>& landmark_edges() const { return landmark_edges_; }
  size_t num_landmarks() const { return landmarks_.size(); }
  /// Places every landmark at the mean of its observations from the current pose estimates
  /// (done by solve() after set_estimates() moved the poses, e.g. a LAGO re-initialisation).
  void initialize_landmarks();

  /// Solves from the current estimates and stores the result. With no prior the gauge is fixed
  /// by holding the first node constant. An empty graph "converges" trivially.
  PoseGraphSolveResult solve(const PoseGraphSolveOptions& options = {});
  /// The cost of the graph at its current estimates (as PoseGraphSolveResult::final_cost), without solving.
  double evaluate_cost();

 private:
  struct NodeState {
    double pose[3] = {0, 0, 0};  ///< x_m, y_m, yaw_rad: one Ceres parameter block
  };
  struct Problem;  ///< the live Ceres problem (keyframe_pose_graph.cpp)
  void sync_problem();
  void sync_landmarks();  ///< adds new landmark blocks to the live problem (keyframe_pose_graph.cpp)

  KeyframePoseGraphOptions options_;
  std::unique_ptr<Problem> problem_;
  std::map<KeyframeId, NodeState> nodes_;  ///< std::map: stable addresses for Ceres blocks
  std::vector<PoseGraphEdge> edges_;
  std::map<KeyframeId, PosePrior> priors_;
  struct LandmarkState {
    double p[2] = {0, 0};  ///< x_m, y_m: one Ceres parameter block
  };
  std::map<PointNodeId, LandmarkState> landmarks_;  ///< std::map: stable addresses for Ceres blocks
  std::vector<LandmarkEdge> landmark_edges_;
  std::set<KeyframeId> landmark_sources_;
  bool landmarks_need_init_ = false;
};

}  // namespace cairn::base
