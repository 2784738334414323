#pragma once
// Compact wire form of a laser scan: ranges quantised to millimetres (uint16), then zstd.
// A 361-beam scan goes from 1444 bytes of floats to ~300-500 bytes.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/laser_scan.h"

namespace cairn {

struct ScanCodecOptions {
  int zstd_level = 3;
};

/// Encodes geometry + quantised ranges. Invalid readings (NaN, <= range_min) become 0,
/// no-return readings (>= range_max) become 65535. The stamp is not encoded (messages carry it).
std::vector<uint8_t> encode_scan(const LaserScan& scan, const ScanCodecOptions& options = {});

/// Decodes; std::nullopt with `error` set when the bytes are truncated or corrupt.
std::optional<LaserScan> decode_scan(const std::vector<uint8_t>& bytes, std::string* error = nullptr);

/// zstd helpers shared by every compressed payload (scans, clouds).
std::vector<uint8_t> zstd_compress(const uint8_t* data, size_t size, int level);
std::optional<std::vector<uint8_t>> zstd_decompress(const std::vector<uint8_t>& bytes, size_t max_size,
                                                    std::string* error = nullptr);

}  // namespace cairn
