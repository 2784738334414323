#pragma once
// The way back: the places the robot has driven through (a crumb every spacing_m), joined where its
// path crossed itself, as a graph. When the robot's own map no longer shows a way home (its scans
// were mapped at drifting poses and a doorway closed up in it), the robot retraces its own steps,
// which it has driven already, still stopped by its laser for anything in the way. Pure.
#include <Eigen/Core>
#include <vector>

namespace cairn::agent {

struct BreadcrumbOptions {
  double spacing_m = 0.5;  ///< a new crumb once the robot is this far from the last one
  double join_m = 0.6;     ///< crumbs this close are joined (the path crossed itself there)
};

class Breadcrumbs {
 public:
  explicit Breadcrumbs(const BreadcrumbOptions& options = {}) : options_(options) {}
  /// The robot is at `position_m` (its local frame).
  void add(const Eigen::Vector2d& position_m);
  /// The shortest way along the crumbs from the crumb nearest `from_m` to the one nearest `to_m`
  /// (from_m first, to_m last); empty when there are no crumbs.
  std::vector<Eigen::Vector2d> way(const Eigen::Vector2d& from_m, const Eigen::Vector2d& to_m) const;
  size_t size() const { return crumbs_.size(); }

 private:
  size_t nearest(const Eigen::Vector2d& p_m) const;
  BreadcrumbOptions options_;
  std::vector<Eigen::Vector2d> crumbs_;
};

}  // namespace cairn::agent
