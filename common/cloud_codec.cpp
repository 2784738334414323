#include "common/cloud_codec.h"

#include <cmath>
#include <cstring>

#include "common/scan_codec.h"

namespace cairn {
namespace {
constexpr uint32_t kMagic = 0x43434C31;  // "CCL1"
constexpr size_t kPointBytes = 9;
constexpr size_t kMaxPoints = 1u << 22;

int16_t quantise_mm(float v) {
  const float mm = std::round(v * 1000.f);
  return int16_t(std::fmax(-32767.f, std::fmin(32767.f, std::isfinite(mm) ? mm : 0.f)));
}
}  // namespace

std::vector<uint8_t> encode_cloud(const ColoredCloud& cloud, int zstd_level) {
  std::vector<uint8_t> raw(8 + kPointBytes * cloud.size());
  const uint32_t n = uint32_t(cloud.size());
  std::memcpy(raw.data(), &kMagic, 4);
  std::memcpy(raw.data() + 4, &n, 4);
  // Structure of arrays (all x, then y, z, r, g, b) compresses better than interleaved points.
  uint8_t* p = raw.data() + 8;
  for (int axis = 0; axis < 3; ++axis) {
    for (const auto& pt : cloud) {
      const int16_t q = quantise_mm(axis == 0 ? pt.x : axis == 1 ? pt.y : pt.z);
      std::memcpy(p, &q, 2);
      p += 2;
    }
  }
  for (const auto& pt : cloud) *p++ = pt.r;
  for (const auto& pt : cloud) *p++ = pt.g;
  for (const auto& pt : cloud) *p++ = pt.b;
  return zstd_compress(raw.data(), raw.size(), zstd_level);
}

std::optional<ColoredCloud> decode_cloud(const std::vector<uint8_t>& bytes, std::string* error) {
  auto raw = zstd_decompress(bytes, 8 + kPointBytes * kMaxPoints, error);
  if (!raw) return std::nullopt;
  uint32_t magic = 0, n = 0;
  if (raw->size() >= 8) {
    std::memcpy(&magic, raw->data(), 4);
    std::memcpy(&n, raw->data() + 4, 4);
  }
  if (magic != kMagic || raw->size() != 8 + kPointBytes * size_t(n)) {
    if (error) *error = "cloud payload has a bad magic or point count";
    return std::nullopt;
  }
  ColoredCloud cloud(n);
  const uint8_t* p = raw->data() + 8;
  for (int axis = 0; axis < 3; ++axis) {
    for (auto& pt : cloud) {
      int16_t q;
      std::memcpy(&q, p, 2);
      p += 2;
      (axis == 0 ? pt.x : axis == 1 ? pt.y : pt.z) = q * 1e-3f;
    }
  }
  for (auto& pt : cloud) pt.r = *p++;
  for (auto& pt : cloud) pt.g = *p++;
  for (auto& pt : cloud) pt.b = *p++;
  return cloud;
}

}  // namespace cairn
