#include "base_station/core/keyframe_pose_graph.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <memory>
#include <set>
#include <unordered_set>

#include "base_station/core/keyframe_pose_graph_costs.h"
#include "common/se2_relative_pose_residual.h"

namespace cairn::base {
namespace {

using namespace keyframe_pose_graph_costs;

bool finite(const SE2& T) { return T.vector().allFinite(); }

}  // namespace

const char* to_string(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kOdometry:
      return "odometry";
    case EdgeKind::kLoop:
      return "loop";
    case EdgeKind::kPrior:
      return "prior";
  }
  return "unknown";
}

/// The live Ceres problem and what of the graph it already holds.
struct KeyframePoseGraph::Problem {
  Problem() : problem(make_options()) {}
  static ceres::Problem::Options make_options() {
    ceres::Problem::Options o;
    o.enable_fast_removal = true;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }
  ceres::AutoDiffManifold<PoseManifold, 3, 3> manifold;
  ceres::Problem problem;
  size_t edges_added = 0;
  /// Per added edge, its residual's functor (the one of the graph's residual type; the other
  /// nullptr), owned by Ceres: set_edge_measurement() rewrites the measurement in place.
  std::vector<Se2RelativePoseResidual*> relative_residuals;
  std::vector<SeSyncResidual*> sesync_residuals;
  std::vector<KeyframeId> new_nodes;  ///< added to the graph since the last sync
  std::vector<ceres::ResidualBlockId> prior_blocks;
  bool priors_dirty = true;
  std::optional<KeyframeId> gauge;  ///< node held constant when there is no prior
  size_t landmark_edges_added = 0;
  std::set<PointNodeId> landmarks_added;
};

KeyframePoseGraph::KeyframePoseGraph(const KeyframePoseGraphOptions& options) : options_(options) {}
KeyframePoseGraph::~KeyframePoseGraph() = default;
KeyframePoseGraph::KeyframePoseGraph(KeyframePoseGraph&&) noexcept = default;
KeyframePoseGraph& KeyframePoseGraph::operator=(KeyframePoseGraph&&) noexcept = default;
KeyframePoseGraph::KeyframePoseGraph(const KeyframePoseGraph& o)
    : options_(o.options_),
      nodes_(o.nodes_),
      edges_(o.edges_),
      priors_(o.priors_),
      landmarks_(o.landmarks_),
      landmark_edges_(o.landmark_edges_),
      landmark_sources_(o.landmark_sources_),
      landmarks_need_init_(o.landmarks_need_init_) {}
KeyframePoseGraph& KeyframePoseGraph::operator=(const KeyframePoseGraph& o) {
  if (this != &o) {
    problem_.reset();
    options_ = o.options_;
    nodes_ = o.nodes_;
    edges_ = o.edges_;
    priors_ = o.priors_;
    landmarks_ = o.landmarks_;
    landmark_edges_ = o.landmark_edges_;
    landmark_sources_ = o.landmark_sources_;
    landmarks_need_init_ = o.landmarks_need_init_;
  }
  return *this;
}

bool KeyframePoseGraph::add_node(KeyframeId id, const SE2& T) {
  if (nodes_.count(id) || !finite(T)) return false;
  nodes_[id] = NodeState{{T.x(), T.y(), T.yaw()}};
  if (problem_) problem_->new_nodes.push_back(id);
  return true;
}

bool KeyframePoseGraph::set_estimate(KeyframeId id, const SE2& T) {
  auto it = nodes_.find(id);
  if (it == nodes_.end() || !finite(T)) return false;
  it->second = NodeState{{T.x(), T.y(), T.yaw()}};
  return true;
}

void KeyframePoseGraph::set_estimates(const std::map<KeyframeId, SE2>& estimates) {
  for (const auto& [id, T] : estimates) set_estimate(id, T);
  landmarks_need_init_ = !landmarks_.empty();  // their old positions belong to the old poses
}

bool KeyframePoseGraph::add_edge(const PoseGraphEdge& edge) {
  if (edge.kind == EdgeKind::kPrior || edge.from == edge.to) return false;
  if (!nodes_.count(edge.from) || !nodes_.count(edge.to)) return false;
  if (!finite(edge.T_from_to) || !sqrt_information(edge.information)) return false;
  edges_.push_back(edge);
  return true;
}

bool KeyframePoseGraph::set_edge_measurement(size_t index, const SE2& T_from_to, const Eigen::Matrix3d& information) {
  if (index >= edges_.size() || !finite(T_from_to)) return false;
  const std::optional<Eigen::Matrix3d> sqrt_info = sqrt_information(information);
  if (!sqrt_info) return false;
  edges_[index].T_from_to = T_from_to;
  edges_[index].information = information;
  if (problem_ && index < problem_->edges_added) {
    if (Se2RelativePoseResidual* r = problem_->relative_residuals[index]) {
      *r = Se2RelativePoseResidual(T_from_to, *sqrt_info, YawWrap::kFloor);
    }
    if (SeSyncResidual* r = problem_->sesync_residuals[index]) *r = SeSyncResidual(T_from_to, information);
  }
  return true;
}

bool KeyframePoseGraph::set_prior(const PosePrior& prior) {
  if (!nodes_.count(prior.node) || !finite(prior.T_world_node) || !sqrt_information(prior.information)) {
    return false;
  }
  priors_[prior.node] = prior;
  if (problem_) problem_->priors_dirty = true;
  return true;
}

bool KeyframePoseGraph::remove_prior(KeyframeId id) {
  if (priors_.erase(id) == 0) return false;
  if (problem_) problem_->priors_dirty = true;
  return true;
}

std::optional<SE2> KeyframePoseGraph::estimate(KeyframeId id) const {
  auto it = nodes_.find(id);
  if (it == nodes_.end()) return std::nullopt;
  return SE2(it->second.pose[0], it->second.pose[1], it->second.pose[2]);
}

std::map<KeyframeId, SE2> KeyframePoseGraph::estimates() const {
  std::map<KeyframeId, SE2> out;
  for (const auto& [id, n] : nodes_) out.emplace_hint(out.end(), id, SE2(n.pose[0], n.pose[1], n.pose[2]));
  return out;
}

void KeyframePoseGraph::sync_problem() {
  if (!problem_) {
    problem_ = std::make_unique<Problem>();
    for (const auto& [id, n] : nodes_) problem_->new_nodes.push_back(id);
  }
  Problem& p = *problem_;
  for (KeyframeId id : p.new_nodes) p.problem.AddParameterBlock(nodes_.at(id).pose, 3, &p.manifold);
  p.new_nodes.clear();
  for (; p.edges_added < edges_.size(); ++p.edges_added) {
    const PoseGraphEdge& e = edges_[p.edges_added];
    ceres::CostFunction* cost = nullptr;
    SeSyncResidual* sesync = nullptr;
    Se2RelativePoseResidual* relative = nullptr;
    if (options_.residual == EdgeResidualType::kSeSync) {
      cost = new ceres::AutoDiffCostFunction<SeSyncResidual, 3, 3, 3>(
          sesync = new SeSyncResidual(e.T_from_to, e.information));
    } else {
      // The shared edge residual (common/se2_relative_pose_residual.h), yaw wrapped by floor as the
      // manifold wraps it.
      cost = new ceres::AutoDiffCostFunction<Se2RelativePoseResidual, 3, 3, 3>(
          relative = new Se2RelativePoseResidual(e.T_from_to, *sqrt_information(e.information), YawWrap::kFloor));
    }
    p.sesync_residuals.push_back(sesync);
    p.relative_residuals.push_back(relative);
    const RobustLossOptions& loss = e.kind == EdgeKind::kLoop ? options_.loop_loss : options_.odometry_loss;
    p.problem.AddResidualBlock(cost, make_loss(loss), nodes_.at(e.from).pose, nodes_.at(e.to).pose);
  }
  if (p.priors_dirty) {
    for (ceres::ResidualBlockId id : p.prior_blocks) p.problem.RemoveResidualBlock(id);
    p.prior_blocks.clear();
    for (const auto& [id, prior] : priors_) {
      auto* cost = new ceres::AutoDiffCostFunction<PriorResidual, 3, 3>(
          new PriorResidual(prior.T_world_node, *sqrt_information(prior.information)));
      p.prior_blocks.push_back(p.problem.AddResidualBlock(cost, make_loss(options_.prior_loss), nodes_.at(id).pose));
    }
    p.priors_dirty = false;
  }
  sync_landmarks();
  // Gauge: with no prior, hold the first node constant.
  const std::optional<KeyframeId> gauge =
      priors_.empty() ? std::optional<KeyframeId>(nodes_.begin()->first) : std::nullopt;
  if (p.gauge != gauge) {
    if (p.gauge && nodes_.count(*p.gauge)) p.problem.SetParameterBlockVariable(nodes_.at(*p.gauge).pose);
    if (gauge) p.problem.SetParameterBlockConstant(nodes_.at(*gauge).pose);
    p.gauge = gauge;
  }
}

namespace {

/// A Ceres problem over the residual blocks of `main` that touch the variable blocks: the active
/// pose blocks not constant in `main`, plus the manifold-free (landmark) blocks they observe. Every
/// other block of those residuals is held constant. Shares cost, loss and manifold objects with
/// `main` (which owns them), so building it costs O(window), not O(graph).
struct LocalProblem {
  explicit LocalProblem(const ceres::Problem& main, const std::vector<double*>& active) : problem(options()) {
    std::unordered_set<double*> variable;
    std::vector<double*> order;
    std::vector<ceres::ResidualBlockId> residuals;
    std::unordered_set<ceres::ResidualBlockId> seen;
    auto add_variable = [&](double* block) {
      if (main.IsParameterBlockConstant(block) || !variable.insert(block).second) return;
      order.push_back(block);
    };
    for (double* block : active) add_variable(block);
    for (size_t i = 0; i < order.size(); ++i) {  // grows while landmarks are found
      std::vector<ceres::ResidualBlockId> blocks;
      main.GetResidualBlocksForParameterBlock(order[i], &blocks);
      for (ceres::ResidualBlockId r : blocks) {
        if (!seen.insert(r).second) continue;
        residuals.push_back(r);
        std::vector<double*> params;
        main.GetParameterBlocksForResidualBlock(r, &params);
        const bool from_active_pose = main.GetManifold(order[i]) != nullptr;
        for (double* q : params) {
          if (from_active_pose && main.GetManifold(q) == nullptr) add_variable(q);
        }
      }
    }
    for (ceres::ResidualBlockId r : residuals) {
      std::vector<double*> params;
      main.GetParameterBlocksForResidualBlock(r, &params);
      for (double* q : params) {
        if (problem.HasParameterBlock(q)) continue;
        problem.AddParameterBlock(q, main.ParameterBlockSize(q), const_cast<ceres::Manifold*>(main.GetManifold(q)));
        if (!variable.count(q)) problem.SetParameterBlockConstant(q);
      }
      problem.AddResidualBlock(const_cast<ceres::CostFunction*>(main.GetCostFunctionForResidualBlock(r)),
                               const_cast<ceres::LossFunction*>(main.GetLossFunctionForResidualBlock(r)), params);
    }
    num_variable = int(order.size());
  }
  static ceres::Problem::Options options() {
    ceres::Problem::Options o;
    o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }
  ceres::Problem problem;
  int num_variable = 0;
};

}  // namespace

PoseGraphSolveResult KeyframePoseGraph::solve(const PoseGraphSolveOptions& options) {
  PoseGraphSolveResult result;
  if (nodes_.empty()) {
    result.converged = true;
    result.reason = "empty graph";
    return result;
  }
  sync_problem();
  ceres::Solver::Options so;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  if (options.max_time_s > 0.0) so.max_solver_time_in_seconds = options.max_time_s;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.num_threads = 1;
  so.sparse_linear_algebra_library_type = options.eigen_sparse ? ceres::EIGEN_SPARSE : ceres::SUITE_SPARSE;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  std::vector<double*> moved;  // pose blocks to re-wrap after the solve
  if (options.active_nodes.empty()) {
    ceres::Solve(so, &problem_->problem, &summary);
    for (auto& [id, n] : nodes_) moved.push_back(n.pose);
    result.variable_blocks = problem_->problem.NumParameterBlocks();
  } else {
    // Bounded local update: only the active nodes (and landmarks they observe) move.
    for (KeyframeId id : options.active_nodes) {
      auto it = nodes_.find(id);
      if (it != nodes_.end()) moved.push_back(it->second.pose);
    }
    LocalProblem local(problem_->problem, moved);
    ceres::Solve(so, &local.problem, &summary);
    result.variable_blocks = local.num_variable;
  }
  for (double* pose : moved) pose[2] = normalize_angle(pose[2]);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = int(summary.iterations.size());
  result.reason = summary.message;
  return result;
}

double KeyframePoseGraph::evaluate_cost() {
  if (nodes_.empty()) return 0.0;
  sync_problem();
  double cost = 0.0;
  problem_->problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
  return cost;
}

void KeyframePoseGraph::sync_landmarks() {
  if (landmarks_need_init_) initialize_landmarks();
  Problem& p = *problem_;
  for (auto& [id, l] : landmarks_) {
    if (p.landmarks_added.insert(id).second) p.problem.AddParameterBlock(l.p, 2);
  }
  for (; p.landmark_edges_added < landmark_edges_.size(); ++p.landmark_edges_added) {
    const LandmarkEdge& e = landmark_edges_[p.landmark_edges_added];
    auto* cost = new ceres::AutoDiffCostFunction<RangeBearingResidual, 2, 3, 2>(new RangeBearingResidual(e));
    const bool object = std::holds_alternative<ObjectId>(e.landmark);
    p.problem.AddResidualBlock(cost, make_loss(object ? options_.object_loss : options_.landmark_loss),
                               nodes_.at(e.from).pose, landmarks_.at(e.landmark).p);
  }
}

}  // namespace cairn::base
