#include "sim/reachable_area.h"

namespace cairn::sim {

std::vector<uint8_t> reachable_free_cells(const FloorPlan& plan, const std::vector<Eigen::Vector2d>& starts_m) {
  const int w = plan.width(), h = plan.height();
  std::vector<uint8_t> reached(size_t(w) * size_t(h), 0);
  std::vector<Eigen::Vector2i> stack;
  auto visit = [&](int c, int r) {
    if (!plan.contains(c, r) || plan.wall(c, r)) return;
    uint8_t& cell = reached[size_t(r) * size_t(w) + size_t(c)];
    if (cell) return;
    cell = 1;
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
  return reached;
}

}  // namespace cairn::sim
