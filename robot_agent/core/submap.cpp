#include "robot_agent/core/submap.h"

#include <algorithm>

namespace cairn::agent {

ActiveSubmaps::ActiveSubmaps(const SubmapOptions& options) : options_(options) {
  options_.scans_per_submap = std::max(1, options_.scans_per_submap);
}

void ActiveSubmaps::insert(const SE2& T_local_base, const std::vector<Eigen::Vector2f>& points_base) {
  if (active_.empty() || active_.back().num_scans >= options_.scans_per_submap) {
    active_.emplace_back(options_.grid, T_local_base);
  }
  for (Submap& s : active_) {
    s.grid.insert_scan(T_local_base, points_base);
    ++s.num_scans;
  }
  if (active_.front().num_scans >= 2 * options_.scans_per_submap) {
    active_.front().finished = true;
    finished_.push_back(std::move(active_.front()));
    active_.pop_front();
  }
  ++version_;
}

}  // namespace cairn::agent
