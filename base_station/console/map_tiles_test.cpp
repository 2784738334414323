#include "base_station/console/map_tiles.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <cmath>

#include "base_station/console/console_server.h"

namespace cairn::base {
namespace {

/// A 4 m x 2 m known room at 5 cm: free inside, a wall one cell thick along x = 2 m.
GridCells room() {
  OccupancyGrid grid({}, {0, 0}, {4, 2});
  for (int r = grid.cell_of({0.02, 0.02}).y(); r <= grid.cell_of({3.98, 1.98}).y(); ++r)
    for (int c = grid.cell_of({0.02, 0.02}).x(); c <= grid.cell_of({3.98, 1.98}).x(); ++c)
      grid.update_cell(c, r, c == grid.cell_of({2.02, 0}).x() ? 4.0f : -4.0f);
  return GridCells::from(grid);
}

/// The tile and pixel that show map point p at zoom z (Leaflet's simple CRS, 256 px tiles).
struct PixelOf {
  TileKey key;
  int i, j;
};
PixelOf pixel_of(const Eigen::Vector2d& p, int z) {
  const double px = p.x() * std::ldexp(1.0, z), py = -p.y() * std::ldexp(1.0, z);
  const int tx = int(std::floor(px / 256)), ty = int(std::floor(py / 256));
  return {{z, tx, ty}, int(std::floor(px - 256.0 * tx)), int(std::floor(py - 256.0 * ty))};
}

uint8_t at(const std::vector<uint8_t>& gray, int i, int j) { return gray[size_t(j) * 256 + size_t(i)]; }

TEST(MapTiles, ShowWallsFreeSpaceAndUnknownWhereTheyAreOnTheMap) {
  const GridCells g = room();
  for (int z : {2, 4, 6}) {
    const PixelOf wall = pixel_of({2.025, 1.0}, z), free = pixel_of({1.0, 1.0}, z), outside = pixel_of({1.0, 3.0}, z);
    ASSERT_EQ(wall.key.x, free.key.x);
    const std::vector<uint8_t> tile = tile_pixels(g, wall.key);
    ASSERT_EQ(tile.size(), 256u * 256u);
    EXPECT_EQ(at(tile, wall.i, wall.j), kTileOccupied) << "zoom " << z;
    EXPECT_EQ(at(tile, free.i, free.j), kTileFree) << "zoom " << z;
    if (outside.key.y == wall.key.y) EXPECT_EQ(at(tile, outside.i, outside.j), kTileUnknown);
  }
  // Zoomed far out a pixel covers many cells: the 5 cm wall still shows (a wall over free space).
  const PixelOf far = pixel_of({2.025, 1.0}, -2);
  EXPECT_EQ(at(tile_pixels(g, far.key), far.i, far.j), kTileOccupied);
  // A tile away from the map is all unknown.
  const std::vector<uint8_t> away = tile_pixels(g, {4, 10, 10});
  EXPECT_EQ(std::count(away.begin(), away.end(), kTileUnknown), long(away.size()));
}

TEST(MapTiles, EtagChangesWithThePixelsOnly) {
  GridCells g = room();
  const TileKey key = pixel_of({1.0, 1.0}, 4).key;
  const std::string before = tile_etag(tile_pixels(g, key));
  EXPECT_EQ(tile_etag(tile_pixels(g, key)), before);
  g.cells[size_t(g.height / 2) * size_t(g.width) + 10] = 0;  // one more wall cell
  EXPECT_NE(tile_etag(tile_pixels(g, key)), before);
}

TEST(MapTiles, ZoomOutOfRangeAndBadImagesAreNamed) {
  EXPECT_FALSE(tile_key_error({6, 0, 0}));
  ASSERT_TRUE(tile_key_error({7, 0, 0}));
  EXPECT_EQ(*tile_key_error({-5, 0, 0}), "zoom -5 is outside -4..6");
  EXPECT_TRUE(encode_gray_png(2, 2, std::vector<uint8_t>(3)).empty());
  const std::vector<uint8_t> png = encode_gray_png(2, 2, std::vector<uint8_t>(4, 255));
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(std::string(png.begin(), png.begin() + 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // A grid whose cells do not match its size gives an empty tile, not a read past the end.
  GridCells broken = room();
  broken.cells.resize(10);
  EXPECT_EQ(tile_pixels(broken, {4, 0, -1})[0], kTileUnknown);
}

TEST(MapTiles, TilesAndPolledJsonAreRevalidatedByEtagAndScriptsCompressed) {
  LatestSnapshot latest;
  ConsoleSnapshot s;
  s.grid_cells = room();
  latest.publish(s);
  ConsoleServer server({"127.0.0.1", 0, ""}, [&latest] { return latest.get(); });
  std::string error;
  ASSERT_TRUE(server.start(&error)) << error;
  httplib::Client client("127.0.0.1", server.port());
  const PixelOf p = pixel_of({1.0, 1.0}, 4);
  const std::string path = "/api/tiles/4/" + std::to_string(p.key.x) + "/" + std::to_string(p.key.y) + ".png";
  const auto first = client.Get(path);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->status, 200);
  EXPECT_EQ(first->get_header_value("Content-Type"), "image/png");
  const std::string etag = first->get_header_value("ETag");
  ASSERT_FALSE(etag.empty());
  const auto again = client.Get(path, {{"If-None-Match", etag}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
  EXPECT_TRUE(again->body.empty());
  // The map changed under the tile: the same request gets the new pixels.
  s.grid_cells.cells.assign(s.grid_cells.cells.size(), 0);
  latest.publish(s);
  const auto changed = client.Get(path, {{"If-None-Match", etag}});
  ASSERT_TRUE(changed);
  EXPECT_EQ(changed->status, 200);
  EXPECT_NE(changed->get_header_value("ETag"), etag);
  const auto bad = client.Get("/api/tiles/9/0/0.png");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 404);
  EXPECT_NE(bad->body.find("zoom 9 is outside"), std::string::npos) << bad->body;
  // The JSON the page polls is revalidated the same way: an unchanged list costs a 304.
  const auto layers = client.Get("/api/layers");
  ASSERT_TRUE(layers);
  const auto layers_again = client.Get("/api/layers", {{"If-None-Match", layers->get_header_value("ETag")}});
  ASSERT_TRUE(layers_again);
  EXPECT_EQ(layers_again->status, 304);
  // Scripts go out as text/javascript, which the server compresses (application/javascript it does not).
  const auto script = client.Get("/app.js", {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(script);
  EXPECT_EQ(script->get_header_value("Content-Type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(script->get_header_value("Content-Encoding"), "gzip");
  const auto library = client.Get("/vendor/../../etc/passwd");
  ASSERT_TRUE(library);
  EXPECT_EQ(library->status, 404);
  server.stop();
}

}  // namespace
}  // namespace cairn::base
