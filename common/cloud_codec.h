#pragma once
// Compact wire form of a coloured cloud in an object frame: int16 millimetres per axis (clouds of
// objects span well under +-32 m) + RGB8, then zstd. 15 bytes/point raw -> 9 quantised -> ~5 zstd.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/point_cloud.h"

namespace cairn {

std::vector<uint8_t> encode_cloud(const ColoredCloud& cloud, int zstd_level = 3);
/// nullopt with `error` when the bytes are corrupt or a point is out of range.
std::optional<ColoredCloud> decode_cloud(const std::vector<uint8_t>& bytes, std::string* error = nullptr);

}  // namespace cairn
