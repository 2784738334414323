#include "common/scan_codec.h"

#include <zstd.h>

#include <cmath>
#include <cstring>

namespace cairn {
namespace {

constexpr uint32_t kMagic = 0x43534E31;  // "CSN1"
constexpr uint16_t kNoReturn = 65535;
constexpr size_t kMaxBeams = 1 << 16;

struct Header {
  uint32_t magic;
  uint32_t beams;
  float angle_min_rad, angle_increment_rad, range_min_m, range_max_m;
};

}  // namespace

std::vector<uint8_t> zstd_compress(const uint8_t* data, size_t size, int level) {
  std::vector<uint8_t> out(ZSTD_compressBound(size));
  const size_t n = ZSTD_compress(out.data(), out.size(), data, size, level);
  if (ZSTD_isError(n)) return {};
  out.resize(n);
  return out;
}

std::optional<std::vector<uint8_t>> zstd_decompress(const std::vector<uint8_t>& bytes, size_t max_size,
                                                    std::string* error) {
  const unsigned long long size = ZSTD_getFrameContentSize(bytes.data(), bytes.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > max_size) {
    if (error) *error = "zstd frame is corrupt or too large";
    return std::nullopt;
  }
  std::vector<uint8_t> out(size);
  const size_t n = ZSTD_decompress(out.data(), out.size(), bytes.data(), bytes.size());
  if (ZSTD_isError(n) || n != size) {
    if (error) *error = std::string("zstd: ") + (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "short frame");
    return std::nullopt;
  }
  return out;
}

std::vector<uint8_t> encode_scan(const LaserScan& scan, const ScanCodecOptions& options) {
  std::vector<uint8_t> raw(sizeof(Header) + 2 * scan.ranges_m.size());
  Header h{
      kMagic,          uint32_t(scan.ranges_m.size()), scan.angle_min_rad, scan.angle_increment_rad, scan.range_min_m,
      scan.range_max_m};
  std::memcpy(raw.data(), &h, sizeof(h));
  uint8_t* p = raw.data() + sizeof(Header);
  for (float r : scan.ranges_m) {
    uint16_t q = 0;
    if (!std::isfinite(r) || r <= scan.range_min_m)
      q = 0;
    else if (r >= scan.range_max_m || r * 1000.f >= float(kNoReturn))
      q = kNoReturn;
    else
      q = uint16_t(std::lround(r * 1000.f));
    std::memcpy(p, &q, 2);
    p += 2;
  }
  return zstd_compress(raw.data(), raw.size(), options.zstd_level);
}

std::optional<LaserScan> decode_scan(const std::vector<uint8_t>& bytes, std::string* error) {
  auto raw = zstd_decompress(bytes, sizeof(Header) + 2 * kMaxBeams, error);
  if (!raw) return std::nullopt;
  Header h{};
  if (raw->size() < sizeof(Header)) {
    if (error) *error = "scan payload shorter than its header";
    return std::nullopt;
  }
  std::memcpy(&h, raw->data(), sizeof(h));
  if (h.magic != kMagic || raw->size() != sizeof(Header) + 2 * size_t(h.beams)) {
    if (error) *error = "scan payload has a bad magic or beam count";
    return std::nullopt;
  }
  LaserScan scan;
  scan.angle_min_rad = h.angle_min_rad;
  scan.angle_increment_rad = h.angle_increment_rad;
  scan.range_min_m = h.range_min_m;
  scan.range_max_m = h.range_max_m;
  scan.ranges_m.resize(h.beams);
  const uint8_t* p = raw->data() + sizeof(Header);
  for (uint32_t i = 0; i < h.beams; ++i, p += 2) {
    uint16_t q;
    std::memcpy(&q, p, 2);
    scan.ranges_m[i] = q == 0 ? 0.f : q == kNoReturn ? std::numeric_limits<float>::infinity() : q * 1e-3f;
  }
  return scan;
}

}  // namespace cairn
