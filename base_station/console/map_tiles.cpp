#include "base_station/console/map_tiles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace cairn::base {
namespace {

constexpr uint8_t kOccupied = 0, kFree = 254;

/// The most telling value of the cells [c0, c1] x [r0, r1] (image rows, top first): occupied over
/// free over unknown.
uint8_t most_telling(const GridCells& g, int c0, int c1, int r0, int r1) {
  bool free = false;
  for (int r = r0; r <= r1; ++r) {
    const uint8_t* row = &g.cells[size_t(r) * size_t(g.width)];
    for (int c = c0; c <= c1; ++c) {
      if (row[c] == kOccupied) return kOccupied;
      free = free || row[c] == kFree;
    }
  }
  return free ? kFree : 205;
}

}  // namespace

GridCells GridCells::from(const OccupancyGrid& grid) {
  return {grid.origin_m(), grid.resolution_m(), grid.width(), grid.height(), grid.to_image()};
}

std::optional<std::string> tile_key_error(const TileKey& key, const TileOptions& options) {
  if (key.z < options.min_zoom || key.z > options.max_zoom) {
    return "zoom " + std::to_string(key.z) + " is outside " + std::to_string(options.min_zoom) + ".." +
           std::to_string(options.max_zoom);
  }
  return std::nullopt;
}

std::vector<uint8_t> tile_pixels(const GridCells& g, const TileKey& key, const TileOptions& options) {
  const int n = options.tile_px;
  std::vector<uint8_t> gray(size_t(n) * size_t(n), kTileUnknown);
  if (g.width <= 0 || g.height <= 0 || g.cells.size() != size_t(g.width) * size_t(g.height)) return gray;
  const double m_per_px = std::ldexp(1.0, -key.z);
  // The cells [lo, hi] under a pixel that starts at lo_m along one axis (may fall outside the grid).
  auto cell_span = [&](double lo_m, double origin_m) {
    const double a = (lo_m - origin_m) / g.resolution_m, b = (lo_m + m_per_px - origin_m) / g.resolution_m;
    // A pixel smaller than a cell takes the cell under its centre; a larger one every cell it covers.
    if (b - a <= 1.0) {
      const int c = int(std::floor(0.5 * (a + b)));
      return std::pair<int, int>(c, c);
    }
    return std::pair<int, int>(int(std::floor(a)), int(std::ceil(b)) - 1);
  };
  for (int j = 0; j < n; ++j) {
    const double y_lo_m = -(double(key.y) * n + j + 1) * m_per_px;  // the pixel row's lower edge
    auto [r0, r1] = cell_span(y_lo_m, g.origin_m.y());              // rows from the bottom
    r0 = std::max(r0, 0);
    r1 = std::min(r1, g.height - 1);
    if (r0 > r1) continue;
    for (int i = 0; i < n; ++i) {
      const double x_lo_m = (double(key.x) * n + i) * m_per_px;
      auto [c0, c1] = cell_span(x_lo_m, g.origin_m.x());
      c0 = std::max(c0, 0);
      c1 = std::min(c1, g.width - 1);
      if (c0 > c1) continue;
      const uint8_t v = most_telling(g, c0, c1, g.height - 1 - r1, g.height - 1 - r0);
      if (v == kOccupied || v == kFree)
        gray[size_t(j) * size_t(n) + size_t(i)] = v == kOccupied ? kTileOccupied : kTileFree;
    }
  }
  return gray;
}

std::string etag_of(const void* data, size_t size) {
  uint64_t h = 1469598103934665603ull;
  const auto* bytes = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < size; ++i) h = (h ^ bytes[i]) * 1099511628211ull;
  char text[24];
  std::snprintf(text, sizeof(text), "\"%016llx\"", static_cast<unsigned long long>(h));
  return text;
}

std::vector<uint8_t> encode_gray_png(int width, int height, const std::vector<uint8_t>& gray) {
  std::vector<uint8_t> png;
  if (width <= 0 || height <= 0 || gray.size() != size_t(width) * size_t(height)) return png;
  try {
    const cv::Mat image(height, width, CV_8UC1, const_cast<uint8_t*>(gray.data()));
    if (!cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, 9})) png.clear();
  } catch (const cv::Exception&) {
    png.clear();
  }
  return png;
}

}  // namespace cairn::base
