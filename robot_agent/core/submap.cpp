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
    // The initial extent covers the first scan (beams cut at the inserter's max length) plus a
    // margin for the travel to come, so the grid rarely has to grow (each growth reallocates it).
    const double half = 0.5 * options_.initial_size_m;
    Eigen::Vector2d lo = T_local_base.translation() - Eigen::Vector2d(half, half);
    Eigen::Vector2d hi = T_local_base.translation() + Eigen::Vector2d(half, half);
    const double max_r = options_.inserter.max_ray_length_m;
    for (const auto& p : points_base) {
      const double r = p.norm();
      const Eigen::Vector2d q = T_local_base * (r > max_r ? Eigen::Vector2d(p.cast<double>() * (max_r / r))
                                                          : Eigen::Vector2d(p.cast<double>()));
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    const double margin = options_.initial_margin_m;
    lo -= Eigen::Vector2d(margin, margin);
    hi += Eigen::Vector2d(margin, margin);
    // Align cell boundaries across submaps to multiples of the resolution.
    const Eigen::Vector2d aligned = (lo / options_.resolution_m).array().floor() * options_.resolution_m;
    const int width = std::max(8, int(std::ceil((hi.x() - aligned.x()) / options_.resolution_m)));
    const int height = std::max(8, int(std::ceil((hi.y() - aligned.y()) / options_.resolution_m)));
    s->grid = ProbabilityGrid(aligned, options_.resolution_m, width, height);
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
