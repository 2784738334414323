#pragma once
// The console's reply helpers, shared by its route files (console_server.cpp, console_map_view.cpp).
// Include after <httplib.h>.
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "base_station/console/map_tiles.h"

namespace cairn::base::http {

inline std::optional<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void reply_json(httplib::Response& res, const nlohmann::json& j) {
  res.set_header("Cache-Control", "no-store");
  res.set_content(j.dump(), "application/json");
}

/// JSON the page polls: revalidated by ETag (a hash of the body), so an unchanged answer costs a
/// 304 and no body.
inline void reply_json_revalidated(const httplib::Request& req, httplib::Response& res, const nlohmann::json& j) {
  const std::string body = j.dump();
  const std::string etag = etag_of(body.data(), body.size());
  res.set_header("Cache-Control", "no-cache");
  res.set_header("ETag", etag);
  if (req.get_header_value("If-None-Match") == etag) {
    res.status = 304;
    return;
  }
  res.set_content(body, "application/json");
}

inline void reply_error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

inline void reply_not_found(httplib::Response& res, const std::string& what) {
  reply_error(res, 404, what + " not found");
}

}  // namespace cairn::base::http
