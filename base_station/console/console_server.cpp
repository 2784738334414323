#include "base_station/console/console_server.h"

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "base_station/console/http_reply.h"

#ifndef CAIRN_WEB_DIR
#define CAIRN_WEB_DIR "base_station/console/web"
#endif

namespace cairn::base {
using http::read_file;
using http::reply_error;
using http::reply_json;
using http::reply_not_found;

ConsoleServer::ConsoleServer(const ConsoleOptions& options, SharedProvider provider)
    : options_(options),
      provider_(std::move(provider)),
      web_dir_(options.web_dir.empty() ? std::string(CAIRN_WEB_DIR) : options.web_dir),
      server_(std::make_unique<httplib::Server>()) {
  register_routes();
}

ConsoleServer::ConsoleServer(const ConsoleOptions& options, Provider provider)
    : ConsoleServer(
          options, SharedProvider([p = std::move(provider)] { return std::make_shared<const ConsoleSnapshot>(p()); })) {
}

ConsoleServer::~ConsoleServer() { stop(); }

void ConsoleServer::register_routes() {
  auto snapshot = [this] {
    std::shared_ptr<const ConsoleSnapshot> s = provider_ ? provider_() : nullptr;
    return s ? s : std::make_shared<const ConsoleSnapshot>();
  };
  auto asset = [this](const std::string& name, const std::string& type) {
    return [this, name, type](const httplib::Request&, httplib::Response& res) {
      const std::optional<std::string> body = read_file(web_dir_ + "/" + name);
      if (!body) return reply_not_found(res, name);
      res.set_content(*body, type.c_str());
    };
  };
  server_->Get("/", asset("index.html", "text/html; charset=utf-8"));
  server_->Get("/index.html", asset("index.html", "text/html; charset=utf-8"));
  server_->Get("/app.js", asset("app.js", "text/javascript; charset=utf-8"));
  server_->Get("/common.js", asset("common.js", "text/javascript; charset=utf-8"));
  server_->Get("/control.js", asset("control.js", "text/javascript; charset=utf-8"));
  server_->Get("/align.js", asset("align.js", "text/javascript; charset=utf-8"));
  server_->Get("/mapview.js", asset("mapview.js", "text/javascript; charset=utf-8"));
  server_->Get("/cloud3d.js", asset("cloud3d.js", "text/javascript; charset=utf-8"));
  server_->Get("/report.html", asset("report.html", "text/html; charset=utf-8"));
  server_->Get("/report.js", asset("report.js", "text/javascript; charset=utf-8"));
  server_->Get("/style.css", asset("style.css", "text/css; charset=utf-8"));
  server_->Get("/api/status", [this, snapshot](const httplib::Request& req, httplib::Response& res) {
    nlohmann::json status = snapshot()->status;
    // An acknowledgement shows at once, not with the next snapshot.
    const std::set<std::string> acked = inbox_ ? inbox_->acked_alerts() : std::set<std::string>{};
    if (status.contains("alerts"))
      for (nlohmann::json& a : status["alerts"])
        if (a.contains("key") && acked.count(a["key"].get<std::string>())) a["acked"] = true;
    http::reply_json_revalidated(req, res, status);
  });
  server_->Get("/api/alerts/log", [snapshot](const httplib::Request& req, httplib::Response& res) {
    http::reply_json_revalidated(req, res, snapshot()->alert_log);
  });
  server_->Post("/api/alerts/ack", [this, snapshot](const httplib::Request& req, httplib::Response& res) {
    if (!authorized(req, res)) return;
    const nlohmann::json j = nlohmann::json::parse(req.body, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.contains("key") || !j["key"].is_string())
      return reply_error(res, 400, "the body must be {\"key\": \"<alert key>\"}");
    const std::string key = j["key"];
    bool known = false;
    for (const nlohmann::json& a : snapshot()->alert_log) known = known || a["key"] == key;
    if (!known) return reply_not_found(res, "alert " + key);
    inbox_->ack_alert(key);
    res.status = 202;
    reply_json(res, {{"acked", key}});
  });
  server_->Get("/api/robots", [snapshot](const httplib::Request& req, httplib::Response& res) {
    http::reply_json_revalidated(req, res, snapshot()->robots);
  });
  server_->Get("/api/objects", [snapshot](const httplib::Request& req, httplib::Response& res) {
    http::reply_json_revalidated(req, res, snapshot()->objects);
  });
  server_->Get("/api/map.png", [snapshot](const httplib::Request&, httplib::Response& res) {
    const auto s = snapshot();
    if (s->map_png.empty()) return reply_not_found(res, "map");
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Map-Image", s->map_image.dump());  // where the pixels are: a click names a point
    res.set_content(reinterpret_cast<const char*>(s->map_png.data()), s->map_png.size(), "image/png");
  });
  server_->Get(R"(/api/robots/([0-9]+)/own_map\.png)", [snapshot](const httplib::Request& req, httplib::Response& res) {
    const auto s = snapshot();
    auto it = s->own_maps.find(req.matches[1]);
    if (it == s->own_maps.end() || it->second.empty()) return reply_not_found(res, "own map of an unlinked robot");
    res.set_header("Cache-Control", "no-store");
    res.set_content(reinterpret_cast<const char*>(it->second.data()), it->second.size(), "image/png");
  });
  server_->Get(R"(/api/objects/([0-9]+-[0-9]+)/thumbnail\.jpg)",
               [snapshot](const httplib::Request& req, httplib::Response& res) {
                 const auto s = snapshot();
                 auto it = s->thumbnails.find(req.matches[1]);
                 if (it == s->thumbnails.end() || it->second.empty()) return reply_not_found(res, "thumbnail");
                 // The page's URL carries ?v=<observations>: a newer thumbnail comes under a new URL.
                 res.set_header("Cache-Control", "max-age=3600");
                 res.set_content(reinterpret_cast<const char*>(it->second.data()), it->second.size(), "image/jpeg");
               });
  server_->Get(R"(/api/objects/([0-9]+-[0-9]+)/cloud)",
               [snapshot](const httplib::Request& req, httplib::Response& res) {
                 const auto s = snapshot();
                 auto it = s->clouds.find(req.matches[1]);
                 if (it == s->clouds.end()) return reply_not_found(res, "object");
                 reply_json(res, it->second);
               });
  server_->Get("/api/commands", [this](const httplib::Request& req, httplib::Response& res) {
    http::reply_json_revalidated(req, res, inbox_ ? inbox_->states() : nlohmann::json::array());
  });
  serve_exports();
  serve_map_view();
  server_->Get("/api/events", [this](const httplib::Request&, httplib::Response& res) { stream_events(res); });
  server_->Post(R"(/api/objects/([0-9]{1,6})-([0-9]{1,9})/verdict)",
                [this](const httplib::Request& req, httplib::Response& res) { handle_verdict(req, res); });
  server_->Post("/api/commands",
                [this](const httplib::Request& req, httplib::Response& res) { handle_command(req, res); });
  server_->Post(R"(/api/robots/([0-9]{1,6})/align)",
                [this](const httplib::Request& req, httplib::Response& res) { handle_alignment(req, res); });
}

void ConsoleServer::accept_commands(const std::string& operator_token, CommandInbox* inbox) {
  operator_token_ = operator_token;
  inbox_ = inbox;
}

void ConsoleServer::offer_exports(const std::string& dir) {
  std::lock_guard<std::mutex> lock(exports_mutex_);
  exports_dir_ = dir;
}

std::string ConsoleServer::exports_dir() const {
  std::lock_guard<std::mutex> lock(exports_mutex_);
  return exports_dir_;
}

namespace {

/// The export files a console hands out, by extension (not the journal: it is live, and the base's).
const char* export_type(const std::string& name) {
  static const std::map<std::string, const char*> types = {{".png", "image/png"},
                                                           {".pgm", "image/x-portable-graymap"},
                                                           {".yaml", "text/yaml"},
                                                           {".csv", "text/csv"},
                                                           {".geojson", "application/geo+json"},
                                                           {".json", "application/json"},
                                                           {".ply", "application/octet-stream"},
                                                           {".bt", "application/octet-stream"},
                                                           {".g2o", "text/plain"}};
  const auto dot = name.rfind('.');
  const auto it = dot == std::string::npos ? types.end() : types.find(name.substr(dot));
  return it == types.end() ? nullptr : it->second;
}

}  // namespace

void ConsoleServer::serve_exports() {
  server_->Get("/api/exports", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string dir = exports_dir();
    nlohmann::json files = nlohmann::json::array();
    std::error_code ec;
    if (!dir.empty()) {
      for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_regular_file(ec) && export_type(name))
          files.push_back({{"name", name}, {"bytes", entry.file_size(ec)}, {"url", "/exports/" + name}});
      }
    }
    std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a["name"] < b["name"]; });
    http::reply_json_revalidated(req, res,
                                 {{"ready", !dir.empty()},
                                  {"note", dir.empty() ? "the exports are written when the mission ends" : ""},
                                  {"files", files}});
  });
  server_->Get(R"(/exports/([A-Za-z0-9_.-]{1,100}))", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string name = req.matches[1].str();
    const std::string dir = exports_dir();
    const char* type = export_type(name);
    if (dir.empty() || !type || name.find("..") != std::string::npos) return reply_not_found(res, "export " + name);
    const std::optional<std::string> body = read_file(dir + "/" + name);
    if (!body) return reply_not_found(res, "export " + name);
    res.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
    res.set_content(*body, type);
  });
}

void ConsoleServer::stream_events(httplib::Response& res) {
  res.set_header("Cache-Control", "no-store");
  // One event whenever the map or the commands changed, the first at once. The stream polls the
  // two version numbers every 50 ms instead of waiting on a condition variable: it keeps the
  // snapshot and the inbox free of any notion of listeners, at no measurable cost for a few pages.
  struct Seen {
    int64_t map = -1, commands = -1;
    std::chrono::steady_clock::time_point last_write = std::chrono::steady_clock::now();
  };
  auto seen = std::make_shared<Seen>();
  ++open_streams_;
  res.set_chunked_content_provider(
      "text/event-stream",
      [this, seen](size_t, httplib::DataSink& sink) {
        for (int i = 0; i < 20 && !stopping_; ++i) {
          const auto s = provider_ ? provider_() : nullptr;
          const int64_t map = s && s->status.contains("version") ? s->status["version"].get<int64_t>() : 0;
          const int64_t commands = inbox_ ? int64_t(inbox_->generation()) : 0;
          if (map != seen->map || commands != seen->commands) {
            seen->map = map;
            seen->commands = commands;
            seen->last_write = std::chrono::steady_clock::now();
            const std::string event =
                "data: " + nlohmann::json{{"map_version", map}, {"commands", commands}}.dump() + "\n\n";
            return sink.write(event.data(), event.size());
          }
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        if (stopping_ || !sink.is_writable()) return false;
        if (std::chrono::steady_clock::now() - seen->last_write > std::chrono::seconds(10)) {
          seen->last_write = std::chrono::steady_clock::now();
          const std::string keep_alive = ": still here\n\n";  // proxies and the browser see a live stream
          return sink.write(keep_alive.data(), keep_alive.size());
        }
        return true;
      },
      [this](bool) { --open_streams_; });  // the page closed (or the server stops)
}

bool ConsoleServer::authorized(const httplib::Request& req, httplib::Response& res) const {
  if (!inbox_ || operator_token_.empty()) {
    reply_error(res, 403, "commands are off: this base was started without an operator token");
    return false;
  }
  if (!operator_token_matches(req.get_header_value("Authorization"), operator_token_)) {
    res.set_header("WWW-Authenticate", "Bearer");
    reply_error(res, 401, "a command needs the operator token (Authorization: Bearer <token>)");
    return false;
  }
  return true;
}

void ConsoleServer::handle_verdict(const httplib::Request& req, httplib::Response& res) {
  if (!authorized(req, res)) return;
  const ObjectId object{RobotId(std::stoi(req.matches[1].str())), std::stoi(req.matches[2].str())};
  const std::string key = req.matches[1].str() + "-" + req.matches[2].str();
  const std::shared_ptr<const ConsoleSnapshot> s = provider_ ? provider_() : nullptr;
  bool known = false;  // shown under this id, now or before a merge
  for (const nlohmann::json& o : s ? s->objects : nlohmann::json::array()) {
    known = known || o["id"] == key;
    for (const auto& alias : o["aliases"]) known = known || alias == key;
  }
  if (!known) return reply_not_found(res, "object " + key);
  std::string error;
  const std::optional<VerdictRequest> request = parse_verdict_request(object, req.body, &error);
  if (!request) return reply_error(res, 400, error);
  inbox_->push_verdict(*request);
  res.status = 202;
  reply_json(res, {{"object", key}, {"verdict", to_string(request->verdict)}});
}

void ConsoleServer::handle_alignment(const httplib::Request& req, httplib::Response& res) {
  if (!authorized(req, res)) return;
  const RobotId robot(std::stoi(req.matches[1].str()));
  const std::shared_ptr<const ConsoleSnapshot> s = provider_ ? provider_() : nullptr;
  std::optional<bool> linked;  // nullopt: not shown
  for (const nlohmann::json& r : s ? s->robots : nlohmann::json::array()) {
    if (r["id"] == robot.value) linked = r["linked"].get<bool>();
  }
  if (!linked) return reply_not_found(res, "robot " + std::to_string(robot.value));
  if (*linked) return reply_error(res, 409, "robot " + std::to_string(robot.value) + " is already on the map");
  std::string error;
  const std::optional<AlignmentRequest> request = parse_alignment_request(robot, req.body, &error);
  if (!request) return reply_error(res, 400, error);
  inbox_->push_alignment(*request);
  res.status = 202;
  reply_json(res, {{"robot", robot.value}, {"state", "pending"}});
}

void ConsoleServer::handle_command(const httplib::Request& req, httplib::Response& res) {
  if (!authorized(req, res)) return;
  const std::shared_ptr<const ConsoleSnapshot> s = provider_ ? provider_() : nullptr;
  CommandCheckContext context = s ? s->command_context : CommandCheckContext{};
  const SearchControls search = inbox_->search();  // newer than the snapshot's
  context.keep_out = search.keep_out();
  context.exploration_paused = search.paused();
  std::vector<RobotId> known;
  for (const auto& [robot, placement] : context.placements) known.push_back(robot);
  std::string error;
  const std::optional<CommandRequest> request = parse_command_request(req.body, known, &error);
  if (!request) return reply_error(res, 400, error);
  if (const auto why = check_command(*request, context)) return reply_error(res, 400, *why);
  res.status = 202;
  reply_json(res, {{"seqs", inbox_->push(*request)}});
}

bool ConsoleServer::start(std::string* error) {
  if (thread_.joinable()) {
    *error = "the console is already started";
    return false;
  }
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.bind_address);
  } else {
    port_ = server_->bind_to_port(options_.bind_address, options_.port) ? options_.port : -1;
  }
  if (port_ <= 0) {
    port_ = -1;
    *error = "cannot start the console on " + options_.bind_address + ":" + std::to_string(options_.port);
    return false;
  }
  listen_ended_ = false;
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listen_ended_ = true;
  });
  // Answer only once it listens (a caller may connect at once), or after 5 s at most.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!server_->is_running() && !listen_ended_ && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

void ConsoleServer::stop() {
  if (!thread_.joinable()) return;
  stopping_ = true;  // open event streams end within one poll
  // httplib's stop() does nothing until its listening loop runs: a stop() right after start() (a
  // mission that ends at once) would leave that loop, and the join, waiting forever. Repeat it.
  while (!listen_ended_) {
    server_->stop();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  thread_.join();
}

bool ConsoleServer::running() const { return thread_.joinable() && server_->is_running(); }

}  // namespace cairn::base
