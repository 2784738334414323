#pragma once
// ConsoleServer: the rescue team's web console (DESIGN.md "Base station" 6), served by cpp-httplib
// on a background thread. It only reads snapshots from a provider (the app thread prepares them
// with make_snapshot), never the mapper. Endpoints:
//   GET /, /app.js, /style.css          web assets from ConsoleOptions::web_dir
//   GET /api/status, /api/robots, /api/objects      JSON
//   GET /api/map.png                                 the rendered map (the report's)
//   GET /api/tiles/<z>/<x>/<y>.png                   the map view's tiles (map_tiles.h), ETag'd
//   GET /api/layers                                  frontiers, saliency, unreachable points
//   GET /api/search, POST /api/search                pause/resume exploration, keep-out areas
//        (search_api.h; same token; 400 a bad request, 409 one that does not apply now)
//   GET /vendor/<file>                               Leaflet, three.js: web_dir/node_modules (npm ci)
//   GET /api/robots/<id>/own_map.png                 an unlinked robot's own map (its frame)
//   GET /api/objects/<robot>-<seq>/thumbnail.jpg     object thumbnail
//   GET /api/objects/<robot>-<seq>/cloud             JSON [[x,y,z,r,g,b],...] (<= 2000 points)
//   GET /api/commands                                the operator's commands and their states
//   GET /api/events                                  Server-Sent Events: the map or the commands changed
//   GET /api/alerts/log, POST /api/alerts/ack {"key"}  the alert log; acknowledge one (operator token)
//   GET /api/exports, /exports/<name>                the mission's exports, once written (offer_exports)
//   POST /api/commands                               a command (command_api.h); needs the operator
//        token: 401 without it, 400 naming the fault of a bad one, 202 {"seqs": [...]} when queued
//   POST /api/objects/<robot>-<seq>/verdict          the operator's verdict on an object (same token;
//        404 for an object never shown under that id)
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "base_station/console/command_api.h"
#include "base_station/console/snapshot.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace cairn::base {

struct ConsoleOptions {
  std::string bind_address = "127.0.0.1";
  int port = 8080;      ///< 0 = pick a free port (see ConsoleServer::port())
  std::string web_dir;  ///< empty = the source tree's console/web (CAIRN_WEB_DIR)
};

class ConsoleServer {
 public:
  using SharedProvider = std::function<std::shared_ptr<const ConsoleSnapshot>()>;
  using Provider = std::function<ConsoleSnapshot()>;

  /// Preferred: no copy per request (e.g. [&latest] { return latest.get(); } with LatestSnapshot).
  ConsoleServer(const ConsoleOptions& options, SharedProvider provider);
  /// Convenience: the provider's snapshot is copied on each request.
  ConsoleServer(const ConsoleOptions& options, Provider provider);
  ~ConsoleServer();
  ConsoleServer(const ConsoleServer&) = delete;
  ConsoleServer& operator=(const ConsoleServer&) = delete;

  /// GET /api/commands lists `inbox`'s states. POST: requests carrying `operator_token` go to
  /// `inbox` once check_command() accepts them against the newest snapshot; commands are off (403)
  /// with an empty token or until this is called. Call before start().
  void accept_commands(const std::string& operator_token, CommandInbox* inbox);

  /// The mission's exports are written (export_all) in `dir`: from now on GET /api/exports lists
  /// them and GET /exports/<name> serves them. Before, the list is empty and says why. Thread-safe.
  void offer_exports(const std::string& dir);

  /// Binds and starts serving on a background thread. False, with `error` set, if the bind fails.
  bool start(std::string* error);
  void stop();
  bool running() const;
  /// The bound port (useful with port 0); -1 before start().
  int port() const { return port_; }
  const std::string& web_dir() const { return web_dir_; }
  /// Pages listening now (open /api/events streams): the base spends on quick snapshots only then.
  int open_streams() const { return open_streams_; }

 private:
  void register_routes();
  void handle_command(const httplib::Request& req, httplib::Response& res);
  void handle_verdict(const httplib::Request& req, httplib::Response& res);
  /// POST /api/robots/<id>/align: an unlinked robot's map placed by the operator (command_api.h).
  void handle_alignment(const httplib::Request& req, httplib::Response& res);
  /// GET /api/events (Server-Sent Events): {"map_version", "commands"} whenever either changed.
  void stream_events(httplib::Response& res);
  void serve_exports();
  void serve_map_view();            ///< console_map_view.cpp: tiles, layers and the map library
  std::string exports_dir() const;  ///< empty until offer_exports()
  /// The operator token checked: false with 403 (commands off) or 401 (no or wrong token) replied.
  bool authorized(const httplib::Request& req, httplib::Response& res) const;

  ConsoleOptions options_;
  SharedProvider provider_;
  std::string web_dir_;
  std::string operator_token_;
  CommandInbox* inbox_ = nullptr;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> listen_ended_{false};  ///< the listening thread returned
  std::atomic<int> open_streams_{0};
  mutable std::mutex exports_mutex_;
  std::string exports_dir_;  ///< empty until offer_exports()
  int port_ = -1;
};

}  // namespace cairn::base
