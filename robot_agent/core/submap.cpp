#include "robot_agent/core/submap.h"

#include <algorithm>
#include <cmath>

namespace cairn::agent {

ActiveSubmaps::ActiveSubmaps(const SubmapOptions& options) : options_(options), inserter_(options.inserter) {
  options_.scans_per_submap = std::max(1, options_.scans_per_submap);
}

SubmapInsertion ActiveSubmaps::insert(const SE2& T_local_base, const std::vector<Eigen::Vector2f>& points_base) {
  SubmapInsertion out;
  const double step_m = active_.empty() ? 0.0 : (T_local_base.translation() - last_pose_.translation()).norm();
  last_pose_ = T_local_base;
  for (auto& s : active_) s->travel_m += step_m;
  if (active_.empty() || active_.back()->num_scans >= options_.scans_per_submap ||
      active_.back()->travel_m >= options_.travel_per_submap_m) {
    auto s = std::make_shared<Submap>();
    s->id = next_id_++;
    s->T_local_submap = T_local_base;
    const int cells = std::max(8, int(std::ceil(options_.initial_size_m / options_.resolution_m)));
    const Eigen::Vector2d origin =
        T_local_base.translation() - 0.5 * options_.resolution_m * Eigen::Vector2d(cells, cells);
    // Align cell boundaries across submaps to multiples of the resolution.
    const Eigen::Vector2d aligned = (origin / options_.resolution_m).array().floor() * options_.resolution_m;
    s->grid = ProbabilityGrid(aligned, options_.resolution_m, cells, cells);
    active_.push_back(std::move(s));
    out.created = true;
  }
  for (auto& s : active_) {
    inserter_.insert(T_local_base, points_base, &s->grid);
    ++s->num_scans;
    out.inserted_into.push_back(s->id);
  }
  if (active_.size() > 2 || active_.front()->num_scans >= 2 * options_.scans_per_submap) {
    active_.front()->finished = true;
    active_.front()->grid.crop_to_known();
    finished_.push_back(active_.front());
    out.finished = active_.front();
    active_.pop_front();
  }
  ++version_;
  return out;
}

}  // namespace cairn::agent
