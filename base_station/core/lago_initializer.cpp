#include "base_station/core/lago_initializer.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <deque>

namespace cairn::base {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

struct Indexed {
  std::map<KeyframeId, int> index;
  std::vector<KeyframeId> ids;
  std::vector<SE2> anchors_pose;  ///< per anchored node
  std::vector<int> anchors;
};

/// Anchors: priors, plus the first node of each connected component that has none.
Indexed index_graph(const KeyframePoseGraph& graph, std::vector<std::vector<std::pair<int, int>>>* adj) {
  Indexed g;
  for (const auto& [id, pose] : graph.estimates()) {
    g.index[id] = int(g.ids.size());
    g.ids.push_back(id);
  }
  adj->assign(g.ids.size(), {});
  const auto& edges = graph.edges();
  for (size_t k = 0; k < edges.size(); ++k) {
    const int i = g.index.at(edges[k].from), j = g.index.at(edges[k].to);
    (*adj)[i].push_back({j, int(k)});
    (*adj)[j].push_back({i, int(k)});
  }
  for (const auto& [id, prior] : graph.priors()) {
    g.anchors.push_back(g.index.at(id));
    g.anchors_pose.push_back(prior.T_world_node);
  }
  return g;
}

/// Breadth-first spanning-tree yaw of each node, from the anchors; components without an anchor
/// get their first node as one (at its current estimate).
std::vector<double> tree_yaw(const KeyframePoseGraph& graph, Indexed* g,
                             const std::vector<std::vector<std::pair<int, int>>>& adj) {
  const size_t n = g->ids.size();
  std::vector<double> yaw(n, 0.0);
  std::vector<bool> seen(n, false);
  std::deque<int> queue;
  auto visit_from = [&](void) {
    while (!queue.empty()) {
      const int i = queue.front();
      queue.pop_front();
      for (const auto& [j, k] : adj[size_t(i)]) {
        if (seen[size_t(j)]) continue;
        const PoseGraphEdge& e = graph.edges()[size_t(k)];
        const bool forward = g->index.at(e.from) == i;
        yaw[size_t(j)] = yaw[size_t(i)] + (forward ? e.T_from_to.yaw() : -e.T_from_to.yaw());
        seen[size_t(j)] = true;
        queue.push_back(j);
      }
    }
  };
  for (size_t a = 0; a < g->anchors.size(); ++a) {
    const int i = g->anchors[a];
    yaw[size_t(i)] = g->anchors_pose[a].yaw();
    seen[size_t(i)] = true;
    queue.push_back(i);
  }
  visit_from();
  const std::map<KeyframeId, SE2> current = graph.estimates();
  for (size_t i = 0; i < n; ++i) {
    if (seen[i]) continue;
    g->anchors.push_back(int(i));
    g->anchors_pose.push_back(current.at(g->ids[i]));
    yaw[i] = g->anchors_pose.back().yaw();
    seen[i] = true;
    queue.push_back(int(i));
    visit_from();
  }
  return yaw;
}

std::optional<Eigen::VectorXd> solve_normal(int n, const Triplets& triplets, const Eigen::VectorXd& b) {
  Eigen::SparseMatrix<double> H(n, n);
  H.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
  if (solver.info() != Eigen::Success) return std::nullopt;
  Eigen::VectorXd x = solver.solve(b);
  if (solver.info() != Eigen::Success || !x.allFinite()) return std::nullopt;
  return x;
}

std::optional<Eigen::VectorXd> solve_orientations(const KeyframePoseGraph& graph, const Indexed& g,
                                                  const std::vector<double>& tree, double w_anchor) {
  const int n = int(g.ids.size());
  Triplets t;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (const PoseGraphEdge& e : graph.edges()) {
    const int i = g.index.at(e.from), j = g.index.at(e.to);
    const double measured = e.T_from_to.yaw();
    const double wraps = std::round((tree[size_t(j)] - tree[size_t(i)] - measured) / (2.0 * M_PI));
    const double delta = measured + 2.0 * M_PI * wraps;
    const double w = std::max(e.information(2, 2), 1e-9);
    t.emplace_back(i, i, w);
    t.emplace_back(j, j, w);
    t.emplace_back(i, j, -w);
    t.emplace_back(j, i, -w);
    b[i] -= w * delta;
    b[j] += w * delta;
  }
  for (size_t a = 0; a < g.anchors.size(); ++a) {
    const int i = g.anchors[a];
    // Anchor yaw unwrapped to the tree's branch.
    const double yaw = tree[size_t(i)];
    t.emplace_back(i, i, w_anchor);
    b[i] += w_anchor * yaw;
  }
  return solve_normal(n, t, b);
}

std::optional<Eigen::VectorXd> solve_positions(const KeyframePoseGraph& graph, const Indexed& g,
                                               const Eigen::VectorXd& theta, double w_anchor) {
  const int n = int(g.ids.size());
  Triplets t;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * n);
  auto add_block = [&](int r, int c, const Eigen::Matrix2d& m) {
    for (int u = 0; u < 2; ++u) {
      for (int v = 0; v < 2; ++v) t.emplace_back(2 * r + u, 2 * c + v, m(u, v));
    }
  };
  for (const PoseGraphEdge& e : graph.edges()) {
    const int i = g.index.at(e.from), j = g.index.at(e.to);
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(theta[i]).toRotationMatrix();
    const Eigen::Matrix2d W = R * e.information.topLeftCorner<2, 2>() * R.transpose();
    const Eigen::Vector2d d = R * e.T_from_to.translation();
    add_block(i, i, W);
    add_block(j, j, W);
    add_block(i, j, -W);
    add_block(j, i, -W);
    b.segment<2>(2 * i) -= W * d;
    b.segment<2>(2 * j) += W * d;
  }
  for (size_t a = 0; a < g.anchors.size(); ++a) {
    const int i = g.anchors[a];
    add_block(i, i, Eigen::Matrix2d::Identity() * w_anchor);
    b.segment<2>(2 * i) += w_anchor * g.anchors_pose[a].translation();
  }
  return solve_normal(2 * n, t, b);
}

}  // namespace

std::optional<std::map<KeyframeId, SE2>> lago_initialize(const KeyframePoseGraph& graph, const LagoOptions& options) {
  std::map<KeyframeId, SE2> out;
  if (graph.num_nodes() == 0) return out;
  std::vector<std::vector<std::pair<int, int>>> adj;
  Indexed g = index_graph(graph, &adj);
  const std::vector<double> tree = tree_yaw(graph, &g, adj);
  const auto theta = solve_orientations(graph, g, tree, options.anchor_information);
  if (!theta) return std::nullopt;
  const auto p = solve_positions(graph, g, *theta, options.anchor_information);
  if (!p) return std::nullopt;
  for (size_t i = 0; i < g.ids.size(); ++i) out[g.ids[i]] = SE2((*p)[2 * i], (*p)[2 * i + 1], (*theta)[i]);
  return out;
}

}  // namespace cairn::base
