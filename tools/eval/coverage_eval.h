#pragma once
// Exploration coverage scored against the truth: the share of the explorable area (the
// simulator's gt_reachable.pgm, sim/reachable_area.h) that the base's final merged map (map.pgm,
// map_server format, global frame = world frame) has observed, free or occupied. (Counting only
// cells it calls free would miss the one-cell band along every wall that a 5 cm map draws
// thicker than the truth: 3 % of a rubble-strewn floor.) The map is laid over the truth by
// T_world_map, the rigid transform that best aligns the robots' trajectories to theirs
// (MapConsistency): a map that sits half a degree off the world would otherwise count the band in
// the lee of every obstacle as never seen (2-3 % of the collapsed floor), which is its placement's
// error, scored elsewhere, not unexplored area.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/se2.h"

namespace cairn::eval {

/// A map_server image (PGM P5, top row first) with its YAML (resolution, origin).
struct MapImage {
  int width = 0, height = 0;
  double resolution_m = 0;
  Eigen::Vector2d origin_m{0, 0};
  std::vector<uint8_t> pixels;  ///< top row first
  /// The pixel under world point p, or nullopt off the image.
  std::optional<uint8_t> at(const Eigen::Vector2d& p_m) const;
  /// World centre of the pixel at (col, row counted from the bottom).
  Eigen::Vector2d centre_m(int col, int row_from_bottom) const;
};

/// Reads `<stem>.yaml` and the image it names; throws InputError naming the file and what is wrong.
MapImage read_map_image(const std::string& yaml_path);

struct CoverageScore {
  double reachable_m2 = 0;  ///< the explorable area
  double covered_m2 = 0;    ///< of it, observed on the final map
  double fraction() const { return reachable_m2 > 0 ? covered_m2 / reachable_m2 : 0.0; }
};

/// nullopt when the ground truth has no gt_reachable.yaml (an older recording); throws InputError
/// for a malformed file or a missing map.yaml.
std::optional<CoverageScore> evaluate_coverage(const std::string& ground_truth_dir, const std::string& results_dir,
                                               const SE2& T_world_map = SE2());

}  // namespace cairn::eval
