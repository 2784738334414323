#pragma once
// A plain coloured point cloud, so interfaces stay free of PCL headers (PCL stays inside the few
// .cpp files that need it; see pcl_conversions.h).
#include <cstdint>
#include <vector>

namespace cairn {

struct ColoredPoint {
  float x = 0.f, y = 0.f, z = 0.f;  ///< metres
  uint8_t r = 0, g = 0, b = 0;
};
using ColoredCloud = std::vector<ColoredPoint>;

}  // namespace cairn
