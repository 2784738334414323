#pragma once
#include <array>
// Test and benchmark helpers: a synthetic polygonal world ray-cast analytically, a synthetic RGB-D
// camera, and the first scans of a CARMEN log (via common/carmen_log).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "common/laser_scan.h"
#include "common/se2.h"
#include "common/sensors.h"

namespace cairn::agent::testing {

struct Segment {
  Eigen::Vector2d a, b;
};

/// A 12 m x 10 m room with a notch, an inner wall and two pillars, rotated by `yaw_rad`.
std::vector<Segment> make_room(double yaw_rad = 0.3);

/// Ray-casts `num_beams` over 360 deg from `T_world_base`; `noise_sigma_m` with a seeded generator.
LaserScan ray_cast(const std::vector<Segment>& world, const SE2& T_world_base, StampNs stamp_ns, int num_beams = 360,
                   double noise_sigma_m = 0.0, unsigned seed = 1);

/// A 160x120 RGB-D frame; draws a square object of `size_m` in `rgb` (default victim red) at world
/// point `object_world` when visible (constant depth = its distance along the optical axis). Camera
/// looks along base x.
RgbdFrame render_rgbd(const SE2& T_world_base, const Eigen::Vector3d& object_world, double size_m, StampNs stamp_ns,
                      const std::array<uint8_t, 3>& rgb = {{220, 30, 30}});
/// The camera mounting used by render_rgbd: optical frame at (0.1, 0, 0.4) in the base, looking along x.
Eigen::Isometry3d test_T_base_camera();
/// A 320x240 RGB-D frame (fx = fy = 260, centred) of a grey wall 4 m ahead, with that mounting.
RgbdFrame grey_wall_frame();
/// Paints a size x size px square with its top-left corner at (u0, v0) in (r, g, b) at depth_mm.
void paint_square(RgbdFrame* f, int u0, int v0, int size, uint8_t r, uint8_t g, uint8_t b, uint16_t depth_mm);

struct CarmenScan {
  LaserScan scan;
  SE2 pose;  ///< corrected pose from the log
};
/// The first `max_scans` laser records of a CARMEN log; nullopt when the file cannot be opened.
std::optional<std::vector<CarmenScan>> read_carmen_flaser(const std::string& path, int max_scans);

}  // namespace cairn::agent::testing
