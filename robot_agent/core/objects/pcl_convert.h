#pragma once
// Internal to cairn_agent_objects: ColoredCloud <-> pcl::PointCloud<PointXYZRGB>. Include only from
// .cpp files that already pay for PCL headers.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>

#include "common/point_cloud.h"

namespace cairn::agent {

inline pcl::PointCloud<pcl::PointXYZRGB>::Ptr to_pcl(const ColoredCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr out(new pcl::PointCloud<pcl::PointXYZRGB>);
  out->reserve(cloud.size());
  for (const ColoredPoint& p : cloud) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    pcl::PointXYZRGB q;
    q.x = p.x, q.y = p.y, q.z = p.z;
    q.r = p.r, q.g = p.g, q.b = p.b;
    out->push_back(q);
  }
  return out;
}

inline ColoredCloud from_pcl(const pcl::PointCloud<pcl::PointXYZRGB>& cloud) {
  ColoredCloud out;
  out.reserve(cloud.size());
  for (const auto& q : cloud) out.push_back(ColoredPoint{q.x, q.y, q.z, q.r, q.g, q.b});
  return out;
}

}  // namespace cairn::agent
