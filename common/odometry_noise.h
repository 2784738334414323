#pragma once
// Seeded synthetic odometry for logs that carry none (GMapping-corrected CARMEN logs): the
// reference trajectory is differentiated into per-step motions, each step is corrupted with
// Gaussian noise whose standard deviation grows with the distance travelled in that step
// (translation: a fraction of the step length; rotation: radians per metre, plus a little per
// radian turned), and the noisy steps are integrated again, so the drift grows like a random walk
// with the distance travelled, as with wheel odometry.
#include <cstdint>
#include <vector>

#include "common/se2.h"

namespace cairn {

struct OdometryNoiseOptions {
  double translation_noise_per_m = 0.10;                 ///< sigma of the step length error, per metre
  double rotation_noise_rad_per_m = 3.0 * M_PI / 180.0;  ///< sigma of the yaw error, per metre
  double rotation_noise_rad_per_rad = 0.02;              ///< sigma of the yaw error, per radian turned
  uint32_t seed = 1;
};

/// Noisy odometry poses for the reference poses `T_world_base` (same length; the first is kept).
std::vector<SE2> add_odometry_noise(const std::vector<SE2>& T_world_base, const OdometryNoiseOptions& options = {});

}  // namespace cairn
