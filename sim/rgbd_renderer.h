#pragma once
// CPU ray caster for the simulated RGB-D camera. Walls are the floor-plan walls extruded from the
// floor (z = 0) to wall_height_m, with a floor and a ceiling; objects of interest are 3D primitives
// (yawed box, vertical cylinder, sphere). Per image column one exact 2D grid ray cast finds the wall
// (per pixel when the camera is pitched, since columns are then no longer vertical planes), each
// row then sees floor, wall or ceiling; objects are intersected analytically per pixel inside their
// projected bounding rectangle, and the nearest hit wins (correct occlusion both ways).
// Shading: walls grey, floor brownish, ceiling dark grey, all low saturation with a faint texture
// (for optical flow); objects Lambertian (headlight + overhead light) in their saturated colour, so
// an HSV detector finds them. Depth = z along the optical axis, uint16 millimetres, 0 beyond
// max_depth_m or where nothing is hit, plus Gaussian noise.
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "common/se2.h"
#include "common/sensors.h"
#include "sim/floor_plan.h"
#include "sim/sim_options.h"
#include "sim/world.h"

namespace cairn::sim {

class RgbdRenderer {
 public:
  RgbdRenderer(const CameraOptions& options, FloorPlan plan, double wall_height_m, std::vector<WorldObject> objects);

  /// Renders the view from a robot at T_world_base. When `object_ids` is given it receives, per
  /// pixel (row-major), the id of the object seen there or -1 (ground truth for detector tests).
  /// `movers` are drawn with the world's objects this once (the other robots' bodies and markers).
  RgbdFrame render(const SE2& T_world_base, StampNs stamp_ns, std::mt19937_64& rng,
                   std::vector<int>* object_ids = nullptr, const std::vector<WorldObject>& movers = {}) const;

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  /// Optical frame (z forward, x right, y down) into the base frame (x forward, y left, z up).
  const Eigen::Isometry3d& T_base_camera() const { return T_base_camera_; }
  /// The camera transform of a given options struct (same as T_base_camera()).
  static Eigen::Isometry3d camera_mount(const CameraOptions& options);
  static CameraIntrinsics intrinsics_of(const CameraOptions& options);

 private:
  struct Hit;
  struct ObjectView;
  std::vector<ObjectView> visible_objects(const std::vector<WorldObject>& scene,
                                          const Eigen::Isometry3d& T_world_camera) const;
  Hit background(const Eigen::Vector3d& c, const Eigen::Vector3d& d, const RayHit& wall, double horizontal_norm) const;
  /// Replaces *hit when the object is nearer along world direction d.
  void intersect(const ObjectView& view, const Eigen::Vector3d& d, Hit* hit) const;
  static void shade_pixel(const Hit& hit, const Eigen::Vector3d& d, uint8_t* rgb);

  CameraOptions options_;
  FloorPlan plan_;
  double wall_height_m_;
  std::vector<WorldObject> objects_;
  CameraIntrinsics intrinsics_;
  Eigen::Isometry3d T_base_camera_;
};

}  // namespace cairn::sim
