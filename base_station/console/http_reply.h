#pragma once
// The console's reply helpers, shared by its route files (console_server.cpp, console_map_view.cpp).
// Include after <httplib.h>.
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

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

inline void reply_error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

inline void reply_not_found(httplib::Response& res, const std::string& what) {
  reply_error(res, 404, what + " not found");
}

}  // namespace cairn::base::http
