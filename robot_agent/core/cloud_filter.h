#pragma once
// Point-cloud helpers on cairn::ColoredCloud; PCL stays inside cloud_filter.cpp.
#include <cstddef>

#include "common/point_cloud.h"

namespace cairn::agent {

/// Voxel-grid downsampling (pcl::VoxelGrid: one averaged point per occupied voxel of `leaf_m`).
ColoredCloud voxel_downsample(const ColoredCloud& cloud, double leaf_m);

/// Keeps at most `max_points` by taking evenly spaced points (deterministic).
ColoredCloud cap_points(const ColoredCloud& cloud, size_t max_points);

}  // namespace cairn::agent
