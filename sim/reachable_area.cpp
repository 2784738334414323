#include "sim/reachable_area.h"

#include <cmath>
#include <queue>

namespace cairn::sim {

std::vector<uint8_t> reachable_free_cells(const FloorPlan& plan, const std::vector<Eigen::Vector2d>& starts_m,
                                          const ReachableAreaOptions& o) {
  const int w = plan.width(), h = plan.height();
  const size_t n = size_t(w) * size_t(h);
  auto at = [w](int c, int r) { return size_t(r) * size_t(w) + size_t(c); };
  auto centre = [&](int c, int r) {
    return Eigen::Vector2d(plan.origin_m() + plan.resolution_m() * Eigen::Vector2d(c + 0.5, r + 0.5));
  };
  // 1. Cell centres a robot can drive to: flood fill (4-neighbours) over centres where it fits.
  std::vector<uint8_t> fits(n, 2);  // 2 = not checked yet
  std::vector<uint8_t> drivable(n, 0);
  std::vector<Eigen::Vector2i> stack;
  auto visit = [&](int c, int r) {
    if (!plan.contains(c, r) || drivable[at(c, r)]) return;
    uint8_t& f = fits[at(c, r)];
    if (f == 2) f = plan.disc_free(centre(c, r), o.robot_radius_m) ? 1 : 0;
    if (!f) return;
    drivable[at(c, r)] = 1;
    stack.emplace_back(c, r);
  };
  for (const auto& s : starts_m) {
    const Eigen::Vector2i c = plan.cell_of(s);
    visit(c.x(), c.y());
  }
  while (!stack.empty()) {
    const Eigen::Vector2i c = stack.back();
    stack.pop_back();
    visit(c.x() + 1, c.y());
    visit(c.x() - 1, c.y());
    visit(c.x(), c.y() + 1);
    visit(c.x(), c.y() - 1);
  }
  // 2. Free cells within view_m of a drivable centre, through free cells (Dijkstra, 8-neighbours):
  //    what a robot sees from up close, never through a wall.
  std::vector<double> dist(n, INFINITY);
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t i = 0; i < n; ++i) {
    if (drivable[i]) {
      dist[i] = 0;
      queue.push({0.0, i});
    }
  }
  const double res = plan.resolution_m();
  std::vector<uint8_t> reached(n, 0);
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    reached[i] = 1;
    const int c = int(i % size_t(w)), r = int(i / size_t(w));
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        const int cc = c + dc, rr = r + dr;
        if ((dc == 0 && dr == 0) || !plan.contains(cc, rr) || plan.wall(cc, rr)) continue;
        const double nd = d + res * ((dc && dr) ? M_SQRT2 : 1.0);
        if (nd <= o.view_m && nd < dist[at(cc, rr)]) {
          dist[at(cc, rr)] = nd;
          queue.push({nd, at(cc, rr)});
        }
      }
    }
  }
  return reached;
}

}  // namespace cairn::sim
