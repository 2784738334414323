#pragma once
// The paper's saliency map carried into the metric map (seed §3.4, attentive exploration): the
// salient pixels of a frame are placed on the floor through the depth image, pooled per floor cell,
// and sent with the next keyframe (Keyframe::salient), so that the base can draw a saliency layer
// over the global map and steer robots toward salient openings first.
//
// Which pixels count: the fused saliency (saliency.h) is normalised per frame, so every frame has a
// "most salient" pixel even when it shows only grey walls; it is multiplied by the absolute colour
// cue (saturation x value) so that a grey frame contributes nothing and a colourful surface (a
// victim's clothes, a hazard sign) seen from afar contributes most. Pure: frames in, points out.
#include <map>
#include <utility>
#include <vector>

#include "common/keyframe.h"
#include "common/se2.h"
#include "common/sensors.h"
#include "robot_agent/core/objects/saliency.h"

namespace cairn::agent {

struct SaliencyProjectionOptions {
  double min_weight = 0.25;           ///< fused x colour below this is not worth a detour
  double max_range_m = 6.0;           ///< farther depth readings are too sparse on the grid to place
  double min_height_m = 0.05;         ///< the floor itself is not salient
  double max_height_m = 2.0;          ///< nor the ceiling
  double cell_m = 0.25;               ///< points are pooled per floor cell of this size (the strongest kept)
  int max_points_per_keyframe = 200;  ///< the strongest cells when more were seen
};

/// Floor positions (base frame, x forward) of the salient pixels of one frame, the strongest per
/// cell. Pixels without a valid depth reading are skipped. Empty when `maps` is empty.
std::vector<SalientPoint> project_saliency(const RgbdFrame& frame, const SaliencyMaps& maps,
                                           const SaliencyProjectionOptions& options = {});

/// Salient points collected in the robot's local frame between two keyframes, pooled per cell.
class SaliencyPool {
 public:
  explicit SaliencyPool(const SaliencyProjectionOptions& options = {}) : options_(options) {}
  /// Points seen from `T_local_base` (the robot's pose when the frame was taken).
  void add(const SE2& T_local_base, const std::vector<SalientPoint>& points_base);
  /// Everything collected, re-expressed from the keyframe at `T_local_keyframe`, strongest first and
  /// at most max_points_per_keyframe; the pool is empty afterwards.
  std::vector<SalientPoint> take(const SE2& T_local_keyframe);
  bool empty() const { return cells_.empty(); }

 private:
  SaliencyProjectionOptions options_;
  std::map<std::pair<int, int>, SalientPoint> cells_;  ///< local frame, by cell
};

}  // namespace cairn::agent
