#include "robot_agent/core/objects/cloud_filter.h"

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>

#include <cmath>

#include "robot_agent/core/objects/pcl_convert.h"

namespace cairn::agent {

ColoredCloud voxel_downsample(const ColoredCloud& cloud, double leaf_m) {
  if (cloud.empty() || leaf_m <= 0.0) return finite_points(cloud);
  const auto in = to_pcl(cloud);
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(in);
  const float leaf = float(leaf_m);
  grid.setLeafSize(leaf, leaf, leaf);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  grid.filter(out);
  return from_pcl(out);
}

ColoredCloud remove_outliers(const ColoredCloud& cloud, int k, double stddev_mult) {
  const ColoredCloud finite = finite_points(cloud);
  if (k < 1 || finite.size() <= size_t(k)) return finite;
  pcl::StatisticalOutlierRemoval<pcl::PointXYZRGB> sor;
  sor.setInputCloud(to_pcl(finite));
  sor.setMeanK(k);
  sor.setStddevMulThresh(stddev_mult);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  sor.filter(out);
  return from_pcl(out);
}

ColoredCloud cap_points(const ColoredCloud& cloud, size_t max_points) {
  if (cloud.size() <= max_points || max_points == 0) return cloud;
  ColoredCloud out;
  out.reserve(max_points);
  const double step = double(cloud.size()) / double(max_points);
  for (size_t i = 0; i < max_points; ++i) out.push_back(cloud[size_t(i * step)]);
  return out;
}

ColoredCloud transform_cloud(const ColoredCloud& cloud, const Eigen::Isometry3d& T) {
  ColoredCloud out = cloud;
  for (ColoredPoint& p : out) {
    const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
    p.x = float(q.x()), p.y = float(q.y()), p.z = float(q.z());
  }
  return out;
}

ColoredCloud finite_points(const ColoredCloud& cloud) {
  ColoredCloud out;
  out.reserve(cloud.size());
  for (const ColoredPoint& p : cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) out.push_back(p);
  return out;
}

}  // namespace cairn::agent
