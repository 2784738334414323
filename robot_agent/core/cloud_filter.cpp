#include "robot_agent/core/cloud_filter.h"

#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace cairn::agent {

ColoredCloud voxel_downsample(const ColoredCloud& cloud, double leaf_m) {
  if (cloud.empty() || leaf_m <= 0.0) return cloud;
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr in(new pcl::PointCloud<pcl::PointXYZRGB>);
  in->reserve(cloud.size());
  for (const ColoredPoint& p : cloud) {
    pcl::PointXYZRGB q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    q.r = p.r;
    q.g = p.g;
    q.b = p.b;
    in->push_back(q);
  }
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(in);
  const float leaf = float(leaf_m);
  grid.setLeafSize(leaf, leaf, leaf);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  grid.filter(out);
  ColoredCloud result;
  result.reserve(out.size());
  for (const auto& q : out) result.push_back(ColoredPoint{q.x, q.y, q.z, q.r, q.g, q.b});
  return result;
}

ColoredCloud cap_points(const ColoredCloud& cloud, size_t max_points) {
  if (cloud.size() <= max_points || max_points == 0) return cloud;
  ColoredCloud out;
  out.reserve(max_points);
  const double step = double(cloud.size()) / double(max_points);
  for (size_t i = 0; i < max_points; ++i) out.push_back(cloud[size_t(i * step)]);
  return out;
}

}  // namespace cairn::agent
