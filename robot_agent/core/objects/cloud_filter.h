#pragma once
// Point-cloud helpers on cairn::ColoredCloud; PCL stays inside cloud_filter.cpp.
#include <Eigen/Geometry>
#include <cstddef>

#include "common/point_cloud.h"

namespace cairn::agent {

/// Voxel-grid downsampling (pcl::VoxelGrid: one averaged point per occupied voxel of `leaf_m`).
ColoredCloud voxel_downsample(const ColoredCloud& cloud, double leaf_m);

/// Statistical outlier removal (pcl::StatisticalOutlierRemoval): drops points whose mean distance
/// to their `k` neighbours exceeds the cloud's mean by `stddev_mult` standard deviations.
/// Clouds smaller than k + 1 points are returned unchanged.
ColoredCloud remove_outliers(const ColoredCloud& cloud, int k = 12, double stddev_mult = 2.0);

/// Keeps at most `max_points` by taking evenly spaced points (deterministic).
ColoredCloud cap_points(const ColoredCloud& cloud, size_t max_points);

/// Applies a rigid transform to every point.
ColoredCloud transform_cloud(const ColoredCloud& cloud, const Eigen::Isometry3d& T);

/// Removes points with non-finite coordinates.
ColoredCloud finite_points(const ColoredCloud& cloud);

}  // namespace cairn::agent
