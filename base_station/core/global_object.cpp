#include "base_station/core/global_object.h"

#include <cmath>
#include <map>
#include <tuple>

namespace cairn::base {

std::string object_key(ObjectId id) {
  return std::to_string(id.robot.value) + "-" + std::to_string(id.seq);
}

ColoredCloud voxel_downsample(const ColoredCloud& cloud, double voxel_m) {
  if (voxel_m <= 0.0) return cloud;
  struct Acc {
    double x = 0, y = 0, z = 0, r = 0, g = 0, b = 0;
    int n = 0;
  };
  std::map<std::tuple<int64_t, int64_t, int64_t>, Acc> voxels;
  for (const ColoredPoint& p : cloud) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    const auto key = std::make_tuple(int64_t(std::floor(p.x / voxel_m)), int64_t(std::floor(p.y / voxel_m)),
                                     int64_t(std::floor(p.z / voxel_m)));
    Acc& a = voxels[key];
    a.x += p.x; a.y += p.y; a.z += p.z;
    a.r += p.r; a.g += p.g; a.b += p.b;
    ++a.n;
  }
  ColoredCloud out;
  out.reserve(voxels.size());
  for (const auto& [key, a] : voxels) {
    ColoredPoint p;
    p.x = float(a.x / a.n); p.y = float(a.y / a.n); p.z = float(a.z / a.n);
    p.r = uint8_t(std::lround(a.r / a.n)); p.g = uint8_t(std::lround(a.g / a.n));
    p.b = uint8_t(std::lround(a.b / a.n));
    out.push_back(p);
  }
  return out;
}

}  // namespace cairn::base
