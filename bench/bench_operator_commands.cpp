// The operator's command loop, end to end on a live mission: how long from the console's POST to
//   accepted  the base's HTTP answer (202),
//   acked     the robot's acknowledgement visible in GET /api/commands (HTTP -> base -> DDS ->
//             agent -> its status -> base -> the console's list),
//   done      the robot reports it reached the point (driving time included).
// Runs cairn_mission (real time by default), sends robot 0 back and forth between two points
// --commands times, then sends every robot home; prints p50 / p95 / max of each.
//   build/bin/bench_operator_commands [--world worlds/office.yaml] [--commands 10] [--speed 1]
//                                     [--a 6,7.5] [--b 3,7.5]
// (Written here rather than with a load-testing tool: the figure is one operator's loop, not load.)
#include <httplib.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tools/mission/ports.h"

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::string stats(std::vector<double> v) {
  if (v.empty()) return "no samples";
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) { return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))]; };
  char buf[120];
  std::snprintf(buf, sizeof buf, "p50 %7.0f   p95 %7.0f   max %7.0f   (n=%zu)", at(0.5), at(0.95), v.back(), v.size());
  return buf;
}

bool parse_point(const std::string& text, double* x, double* y) {
  return std::sscanf(text.c_str(), "%lf,%lf", x, y) == 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn operator command latency on a live mission"};
  std::string world = std::string(CAIRN_SOURCE_DIR) + "/worlds/office.yaml";
  int commands = 10;
  double speed = 1.0;
  std::string a = "6,7.5", b = "3,7.5";
  app.add_option("--world", world, "world YAML (robot 0 is commanded)");
  app.add_option("--commands", commands, "goto commands to time")->check(CLI::Range(1, 1000));
  app.add_option("--speed", speed, "simulator speed, times real time (0 = as fast as possible)");
  app.add_option("--a", a, "first point x,y (m, map frame)");
  app.add_option("--b", b, "second point x,y (m, map frame)");
  CLI11_PARSE(app, argc, argv);
  double ax, ay, bx, by;
  if (!parse_point(a, &ax, &ay) || !parse_point(b, &bx, &by)) {
    std::cerr << "bench_operator_commands: --a/--b must be x,y\n";
    return 2;
  }
  const std::string token = "bench0123456789abcdef0123456789ab";
  const int port = cairn::mission::free_port();
  const std::string out = (std::filesystem::temp_directory_path() / "bench_operator_commands").string();
  const std::string bin = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  const std::string cmd = bin + "/cairn_mission --world " + world + " --out " + out + " --port " +
                          std::to_string(port) + " --operator-token " + token + " --speed " + std::to_string(speed) +
                          " --timeout 1800 > " + out + ".log 2>&1";
  auto mission = std::async(std::launch::async, [&] { return std::system(cmd.c_str()); });

  httplib::Client http("127.0.0.1", port);
  http.set_connection_timeout(1);
  const httplib::Headers auth = {{"Authorization", "Bearer " + token}};
  const auto get = [&](const char* path) {
    const auto r = http.Get(path);
    return r && r->status == 200 ? json::parse(r->body, nullptr, false) : json();
  };
  const auto robot0_placed = [&] {
    const json robots = get("/api/robots");
    if (robots.is_array())
      for (const auto& r : robots)
        if (r["id"] == 0 && !r["pose_m"].is_null()) return true;
    return false;
  };
  for (auto until = Clock::now() + std::chrono::minutes(3); !robot0_placed();
       std::this_thread::sleep_for(std::chrono::milliseconds(200))) {
    if (Clock::now() > until) {
      std::cerr << "bench_operator_commands: robot 0 never placed; see " << out << ".log\n";
      return 1;
    }
  }
  std::vector<double> accepted_ms, acked_ms, done_ms;
  int failed = 0;
  for (int i = 0; i < commands; ++i) {
    const bool to_a = i % 2 == 0;
    const json body = {{"robot", 0}, {"kind", "goto"}, {"x_m", to_a ? ax : bx}, {"y_m", to_a ? ay : by}};
    const auto t0 = Clock::now();
    const auto r = http.Post("/api/commands", auth, body.dump(), "application/json");
    if (!r || r->status != 202) {
      std::cerr << "bench_operator_commands: refused: " << (r ? r->body : "no answer") << "\n";
      return 1;
    }
    accepted_ms.push_back(ms_since(t0));
    const int seq = json::parse(r->body)["seqs"][0];
    bool acked = false;
    for (auto until = t0 + std::chrono::seconds(120); Clock::now() < until;) {
      json state;
      const json list = get("/api/commands");
      if (list.is_array())
        for (const auto& c : list)
          if (c["seq"] == seq) state = c["state"];
      if (!acked && state.is_string() && state != "sent") acked = true, acked_ms.push_back(ms_since(t0));
      if (state == "done") {
        done_ms.push_back(ms_since(t0));
        break;
      }
      if (state == "failed") {
        ++failed;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  http.Post("/api/commands", auth, json{{"robot", "all"}, {"kind", "home"}}.dump(), "application/json");
  mission.wait();
  std::cout << "operator commands on " << world << " at speed " << speed << " (robot 0, " << commands
            << " gotos between (" << a << ") and (" << b << "), ms from the POST)\n"
            << "  accepted (HTTP 202)           " << stats(accepted_ms) << "\n"
            << "  acknowledged by the robot     " << stats(acked_ms) << "\n"
            << "  done (point reached)          " << stats(done_ms) << "\n"
            << "  failed: " << failed << "; mission log: " << out << ".log\n";
  return 0;
}
