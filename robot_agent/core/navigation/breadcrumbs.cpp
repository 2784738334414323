#include "robot_agent/core/navigation/breadcrumbs.h"

#include <limits>
#include <queue>

namespace cairn::agent {

void Breadcrumbs::add(const Eigen::Vector2d& position_m) {
  if (crumbs_.empty() || (position_m - crumbs_.back()).norm() >= options_.spacing_m) crumbs_.push_back(position_m);
}

size_t Breadcrumbs::nearest(const Eigen::Vector2d& p_m) const {
  size_t best = 0;
  for (size_t i = 1; i < crumbs_.size(); ++i) {
    if ((crumbs_[i] - p_m).squaredNorm() < (crumbs_[best] - p_m).squaredNorm()) best = i;
  }
  return best;
}

std::vector<Eigen::Vector2d> Breadcrumbs::way(const Eigen::Vector2d& from_m, const Eigen::Vector2d& to_m) const {
  if (crumbs_.empty()) return {};
  const size_t start = nearest(from_m), goal = nearest(to_m), n = crumbs_.size();
  // Dijkstra over the crumbs: consecutive ones are joined (driven), and so are any two within
  // join_m (O(n^2) neighbours: a crumb every 0.5 m gives ~2000 in 1 km of driving, a few ms).
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<size_t> parent(n, n);
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[start] = 0;
  queue.push({0.0, start});
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    if (i == goal) break;
    for (size_t j = 0; j < n; ++j) {
      const double step = (crumbs_[j] - crumbs_[i]).norm();
      const bool joined = j + 1 == i || i + 1 == j || step <= options_.join_m;
      if (j == i || !joined || d + step >= dist[j]) continue;
      dist[j] = d + step;
      parent[j] = i;
      queue.push({dist[j], j});
    }
  }
  std::vector<Eigen::Vector2d> way{to_m};
  for (size_t i = goal; i != n; i = parent[i]) way.push_back(crumbs_[i]);
  way.push_back(from_m);
  return {way.rbegin(), way.rend()};
}

}  // namespace cairn::agent
