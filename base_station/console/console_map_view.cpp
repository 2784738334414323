// The console's map view routes: the merged grid as tiles (map_tiles.h), the plan's layers, the
// map library itself (Leaflet, installed by npm next to the web files and served from here: the
// field has no internet, so no CDN), and the search controls drawn on the map (search_api.h).
// Eigen (through console_server.h) must come before httplib.h: resolv.h's `_res` macro breaks Eigen.
#include "base_station/console/console_server.h"

#include <httplib.h>

#include <map>
#include <string>

#include "base_station/console/http_reply.h"
#include "base_station/console/map_tiles.h"
#include "base_station/console/search_api.h"

namespace cairn::base {
namespace {

/// The library files the page loads (Leaflet, three.js), by name: the only ones served from node_modules.
const std::map<std::string, std::pair<std::string, std::string>>& vendor_files() {
  static const std::map<std::string, std::pair<std::string, std::string>> files = {
      {"leaflet.js", {"leaflet/dist/leaflet.js", "text/javascript; charset=utf-8"}},
      {"leaflet.css", {"leaflet/dist/leaflet.css", "text/css; charset=utf-8"}},
      {"images/layers.png", {"leaflet/dist/images/layers.png", "image/png"}},
      {"images/layers-2x.png", {"leaflet/dist/images/layers-2x.png", "image/png"}},
      {"three.module.js", {"three/build/three.module.js", "text/javascript; charset=utf-8"}},
      {"three-addons/controls/OrbitControls.js",
       {"three/examples/jsm/controls/OrbitControls.js", "text/javascript; charset=utf-8"}},
  };
  return files;
}

}  // namespace

void ConsoleServer::serve_map_view() {
  server_->Get(R"(/api/tiles/(-?[0-9]{1,3})/(-?[0-9]{1,7})/(-?[0-9]{1,7})\.png)",
               [this](const httplib::Request& req, httplib::Response& res) {
                 const TileKey key{std::stoi(req.matches[1]), std::stoi(req.matches[2]), std::stoi(req.matches[3])};
                 if (const auto error = tile_key_error(key))
                   return http::reply_error(res, 404, "no such tile: " + *error);
                 const auto s = provider_ ? provider_() : nullptr;
                 if (!s) return http::reply_not_found(res, "map");
                 const std::vector<uint8_t> pixels = tile_pixels(s->grid_cells, key);
                 const std::string etag = tile_etag(pixels);
                 // Revalidated on every use: a tile that did not change costs a 304 and no pixels.
                 res.set_header("Cache-Control", "no-cache");
                 res.set_header("ETag", etag);
                 if (req.get_header_value("If-None-Match") == etag) {
                   res.status = 304;
                   return;
                 }
                 const std::vector<uint8_t> png = encode_gray_png(TileOptions{}.tile_px, TileOptions{}.tile_px, pixels);
                 if (png.empty()) return http::reply_error(res, 500, "the tile could not be encoded");
                 res.set_content(reinterpret_cast<const char*>(png.data()), png.size(), "image/png");
               });
  server_->Get("/api/search", [this](const httplib::Request& req, httplib::Response& res) {
    http::reply_json_revalidated(req, res, search_json(inbox_ ? inbox_->search() : SearchControls{}));
  });
  server_->Post("/api/search", [this](const httplib::Request& req, httplib::Response& res) {
    if (!authorized(req, res)) return;
    std::string error;
    const std::optional<SearchControlRequest> request = parse_search_request(req.body, &error);
    if (!request) return http::reply_error(res, 400, error);
    if (const auto why = inbox_->search().check(*request)) return http::reply_error(res, 409, *why);
    inbox_->push_search(*request);
    res.status = 202;
    http::reply_json(res, {{"queued", to_string(request->action)}});
  });
  server_->Get("/api/layers", [this](const httplib::Request& req, httplib::Response& res) {
    const auto s = provider_ ? provider_() : nullptr;
    http::reply_json_revalidated(req, res, s ? s->layers : nlohmann::json::object());
  });
  server_->Get(R"(/vendor/(.{1,60}))", [this](const httplib::Request& req, httplib::Response& res) {
    const auto it = vendor_files().find(req.matches[1].str());
    if (it == vendor_files().end()) return http::reply_not_found(res, "library file " + req.matches[1].str());
    const auto body = http::read_file(web_dir_ + "/node_modules/" + it->second.first);
    if (!body) {
      return http::reply_error(res, 404,
                               "a console library is not installed (" + it->second.first +
                                   "): run scripts/install_deps.sh, which runs npm ci in base_station/console/web");
    }
    res.set_header("Cache-Control", "max-age=3600");
    res.set_content(*body, it->second.second.c_str());
  });
}

}  // namespace cairn::base
