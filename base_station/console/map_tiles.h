#pragma once
// The merged occupancy grid as map tiles for the console's map view (Leaflet, simple CRS): the
// page fetches only the tiles it shows, at the zoom it shows, and a tile that did not change costs a
// 304 (its ETag is a hash of its pixels). Tiles follow Leaflet's L.CRS.Simple with one map unit per
// metre: at zoom z a metre is 2^z pixels, and tile (x, y) covers x in [x s, (x + 1) s) m and
// y in (-(y + 1) s, -y s] m, s = tile_px / 2^z (tile rows grow downwards, map y upwards).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/occupancy_grid.h"

namespace cairn::base {

/// An immutable copy of the grid's cells, taken with each console snapshot.
struct GridCells {
  Eigen::Vector2d origin_m{0, 0};  ///< lower-left corner of cell (0, 0)
  double resolution_m = 0.05;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> cells;  ///< OccupancyGrid::to_image(): top row first, 0 occupied, 254 free, 205 unknown

  static GridCells from(const OccupancyGrid& grid);
};

struct TileOptions {
  int tile_px = 256;
  int min_zoom = -4;  ///< 16 m per pixel
  int max_zoom = 6;   ///< 64 pixels per metre (3.2 per 5 cm cell); Leaflet scales up beyond
};

struct TileKey {
  int z = 0, x = 0, y = 0;
};

/// Why `key` is not a tile (zoom out of range), or nullopt when it is.
std::optional<std::string> tile_key_error(const TileKey& key, const TileOptions& options = {});

/// The shade of an occupied, a free and an unknown pixel (the ROS map_server grey for unknown, which
/// is also the map view's background).
constexpr uint8_t kTileOccupied = 40, kTileFree = 255, kTileUnknown = 205;

/// The tile's pixels, grey levels, top row first. A pixel that covers several cells shows the most
/// telling one (a wall over free space over unknown), so walls stay visible when zoomed out. One
/// grey channel: a tile's PNG is several times smaller than RGBA's (the page's bytes per second).
std::vector<uint8_t> tile_pixels(const GridCells& grid, const TileKey& key, const TileOptions& options = {});

/// A strong ETag for `size` bytes (FNV-1a 64, quoted): the tiles' and the polled JSON's.
std::string etag_of(const void* data, size_t size);
inline std::string tile_etag(const std::vector<uint8_t>& pixels) { return etag_of(pixels.data(), pixels.size()); }

/// PNG bytes of a grey image (best compression); empty if encoding failed.
std::vector<uint8_t> encode_gray_png(int width, int height, const std::vector<uint8_t>& gray);

}  // namespace cairn::base
