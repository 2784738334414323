// cairn_mission: the end-to-end demo. Starts the simulator, one agent per robot and the base
// station as separate processes on a fresh DDS domain, prints progress from the base station's
// console API, then scores the merged map against ground truth and prints a summary.
//   out/<world>/ground_truth  (simulator)   out/<world>/map  (base station exports)
//   out/<world>/logs          (one log per process)   out/<world>/results.json, summary.txt
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "common/errors.h"
#include "common/random_token.h"
#include "dds/domain_lease.h"
#include "sim/world.h"
#include "tools/mission/child_process.h"
#include "tools/mission/mission_report.h"
#include "tools/mission/network_lab.h"
#include "tools/mission/radio_follower.h"
#include "tools/mission/radio_map.h"

namespace fs = std::filesystem;
using cairn::mission::ChildProcess;

namespace {

/// Share of an emulated radio's rate the robots' payload may use together (--link-kbit).
constexpr double kLinkPayloadShare = 0.6;

volatile std::sig_atomic_t g_interrupted = 0;
void on_signal(int) { g_interrupted = 1; }

struct Options {
  std::string world;
  std::string routes;  ///< scripted routes instead of autonomous exploration
  std::string exploration = "coordinated";
  double meet_after_s = -1;  ///< active linking's delay; negative: the base's default
  int64_t seed = -1;         ///< the world's own when negative
  std::string out;
  double speed = 0.0;
  bool serve = false;
  int port = 8080;
  int domain = -1;
  bool secure = false;
  double timeout_s = 900;
  cairn::mission::LinkOptions link;  ///< emulated radio between robots and base (needs root)
  bool radio_model = false;          ///< each robot's link cut where walls and distance say (needs root)
  /// "SIGMA_XY_M,SIGMA_YAW_DEG": the team's rough guess of where every other robot entered.
  std::string entry_hints;
  std::string operator_token;  ///< the console's commands need it (default: a fresh one)
  std::string record;          ///< an MCAP file to record the mission's DDS topics to
  bool ros2 = false;           ///< the base publishes the mission as ROS 2 topics (RViz2, Foxglove)
};

std::string fmt_pose(int id, const cairn::SE2& p) {
  return std::to_string(id) + "," + std::to_string(p.x()) + "," + std::to_string(p.y()) + "," + std::to_string(p.yaw());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn simulated rescue mission, end to end"};
  Options opt;
  app.add_option("--world", opt.world, "world YAML")->required();
  app.add_option("--routes", opt.routes,
                 "scripted routes (worlds/routes/*.yaml): the robots drive them instead of exploring by themselves");
  app.add_option("--exploration", opt.exploration,
                 "coordinated: the base spreads the robots over the frontiers; nearest: each robot its own nearest; "
                 "saliency: coordinated, and frontiers near salient spots the cameras saw go first")
      ->check(CLI::IsMember({"coordinated", "nearest", "saliency"}));
  app.add_option("--meet-after", opt.meet_after_s,
                 "active linking: a robot not on the map this many mission seconds after its first keyframe is "
                 "sent to meet a teammate (0 = never; default: the base's)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", opt.seed, "override the world's random seed (sensor noise)");
  app.add_option("--out", opt.out, "output folder (default out/<world name>)");
  app.add_option("--speed", opt.speed, "simulator speed, times real time (0 = as fast as possible)");
  app.add_flag("--serve", opt.serve, "keep the console up after the mission (Ctrl-C to stop)");
  app.add_option("--port", opt.port, "console port (0 = any free port)");
  app.add_option("--domain", opt.domain, "DDS domain id (default: a fresh one)")->check(CLI::Range(0, 232));
  app.add_option("--timeout", opt.timeout_s, "give up after this many seconds");
  app.add_flag("--secure", opt.secure,
               "DDS Security: a fresh mission CA and one certificate per process (out/security); every "
               "participant authenticated (PKI-DH), every message encrypted (AES-GCM)");
  app.add_option("--entry-hints", opt.entry_hints,
                 "SIGMA_XY_M,SIGMA_YAW_DEG: tell the base roughly where each other robot entered (its true start "
                 "moved by about one sigma), as a rescue team would know it");
  app.add_option("--operator-token", opt.operator_token,
                 "secret the console's commands need (default: a fresh random one, printed in the console's address)");
  app.add_option("--link-loss", opt.link.loss_pct, "emulated radio: % of packets lost each way (needs root)");
  app.add_option("--link-kbit", opt.link.rate_kbit, "emulated radio: rate limit each way in kbit/s (needs root)");
  std::vector<double> cut;
  app.add_option("--link-cut", cut,
                 "AT_S FOR_S: emulated radio: the link goes down AT_S seconds (wall) into the mission "
                 "for FOR_S seconds (needs root)")
      ->expected(2);
  app.add_flag("--radio-model", opt.radio_model,
               "emulated radio: each robot's link is cut while walls and distance put it out of range of the "
               "team's antennas (the world's radio: section, sim/radio_model.h; needs root)");
  app.add_option("--record", opt.record,
                 "record every DDS topic to this MCAP file (ROS 2 bag storage; cairn_replay plays it back)");
  app.add_flag("--ros2", opt.ros2,
               "the base publishes the map, frames, paths and objects as ROS 2 topics (RViz2, Foxglove; docs/ros2.md); "
               "with --record they are recorded too");
  CLI11_PARSE(app, argc, argv);

  cairn::sim::WorldFile wf;
  try {
    cairn::sim::WorldLoadOptions load;
    load.routes_path = opt.routes;  // checked here too: a bad routes file fails before anything starts
    wf = cairn::sim::load_world_file(opt.world, load);
  } catch (const cairn::InputError& e) {
    std::cerr << "cairn_mission: " << e.what() << "\n";
    return 2;
  }
  if (opt.out.empty()) opt.out = "out/" + wf.world.name;
  // A fresh domain, held until this launcher exits, so that concurrent missions never meet.
  std::unique_ptr<cairn::dds::DomainLease> domain_lease;
  if (opt.domain < 0) {
    std::string error;
    domain_lease = cairn::dds::DomainLease::claim({}, &error);
    if (!domain_lease) {
      std::cerr << "cairn_mission: " << error << " (pass --domain)\n";
      return 2;
    }
    opt.domain = domain_lease->domain_id();
  }
  if (opt.port != 0 && !cairn::mission::port_is_free(opt.port)) {
    const int taken = opt.port;
    opt.port = cairn::mission::free_port();
    std::cout << "console port " << taken << " is in use (another console or program listens there): using " << opt.port
              << " instead (--port to choose)\n";
  }
  if (opt.port == 0) opt.port = cairn::mission::free_port();
  const fs::path out(opt.out);
  std::error_code ec;
  fs::remove_all(out / "map", ec);
  fs::remove_all(out / "ground_truth", ec);
  fs::remove_all(out / "logs", ec);
  fs::create_directories(out / "logs", ec);
  if (ec) {
    std::cerr << "cairn_mission: cannot create " << out << ": " << ec.message() << "\n";
    return 2;
  }
  const fs::path bin = fs::canonical("/proc/self/exe").parent_path();
  const fs::path radio_csv = out / "logs" / "radio.csv";
  const int robots = int(wf.world.robots.size());

  // --secure: one identity per process, signed by a CA made for this mission alone.
  const fs::path security = out / "security";
  fs::remove_all(security, ec);
  auto secured = [&](std::vector<std::string> cmd, const std::string& who) {
    if (opt.secure) cmd.insert(cmd.end(), {"--security", (security / who).string()});
    return cmd;
  };
  if (opt.secure) {
    std::string make = "bash '" + (bin / "make_certs.sh").string() + "' '" + security.string() + "' base sim recorder";
    for (const auto& r : wf.world.robots) make += " robot" + std::to_string(r.id.value);
    if (std::system(make.c_str()) != 0) {
      std::cerr << "cairn_mission: cannot make the mission's certificates (" << make << ")\n";
      return 2;
    }
  }

  // With an emulated radio the base station sits behind it in its own network namespace and talks
  // to the agents over UDP only; the sensor topics stay on the robots' side (shared memory).
  std::unique_ptr<cairn::mission::NetworkLab> lab;
  std::string console_host = "127.0.0.1";
  std::vector<std::string> base_cmd, agent_extra;
  if (cut.size() == 2) {
    opt.link.cut_at_s = cut[0];
    opt.link.cut_for_s = cut[1];
  }
  if (opt.link.loss_pct > 0 || opt.link.rate_kbit > 0 || opt.link.cut_at_s >= 0 || opt.radio_model) {
    std::string error;
    lab = cairn::mission::NetworkLab::create(opt.link, &error);
    if (!lab) {
      std::cerr << "cairn_mission: " << error << "\n";
      return 2;
    }
    base_cmd = lab->prefix();
    console_host = lab->base_side_address();
    agent_extra = {"--peer", lab->base_side_address()};
    if (opt.link.rate_kbit > 0) {
      // Each robot sends within an equal share of the shared radio, kept below its rate: the rest
      // carries discovery, heartbeats, acknowledgements and retransmissions of lost packets.
      agent_extra.push_back("--link-budget-kbit");
      agent_extra.push_back(std::to_string(kLinkPayloadShare * opt.link.rate_kbit / robots));
    }
  }
  base_cmd.insert(base_cmd.end(), {(bin / "cairn_base").string(), "--domain", std::to_string(opt.domain), "--out",
                                   (out / "map").string(), "--robots", std::to_string(robots), "--port",
                                   std::to_string(opt.port), "--exploration", opt.exploration});
  if (opt.meet_after_s >= 0) base_cmd.insert(base_cmd.end(), {"--meet-after", std::to_string(opt.meet_after_s)});
  // The team knows where the first robot entered (it anchors the map in world coordinates); where
  // the others started is not told: the base links them by cross-robot loop closures.
  const auto& anchor = wf.world.robots.front();
  base_cmd.push_back("--start");
  base_cmd.push_back(fmt_pose(anchor.id.value, anchor.T_world_start));
  if (!opt.entry_hints.empty()) {
    const auto sigmas = cairn::sim::parse_entry_hint_sigmas(opt.entry_hints);
    if (!sigmas) {
      std::cerr << "cairn_mission: --entry-hints '" << opt.entry_hints
                << "': expected SIGMA_XY_M,SIGMA_YAW_DEG, both positive\n";
      return 2;
    }
    const double sigma_xy_m = sigmas->xy_m, sigma_yaw_deg = sigmas->yaw_deg;
    for (size_t i = 1; i < wf.world.robots.size(); ++i) {
      const cairn::SE2 guess = cairn::sim::entry_hint_guess(wf.world, i, sigma_xy_m, sigma_yaw_deg * M_PI / 180.0);
      std::ostringstream hint;
      hint << wf.world.robots[i].id.value << ',' << guess.x() << ',' << guess.y() << ',' << guess.yaw() * 180.0 / M_PI
           << ',' << sigma_xy_m << ',' << sigma_yaw_deg;
      base_cmd.insert(base_cmd.end(), {"--start-hint", hint.str()});
    }
  }
  if (opt.operator_token.empty()) opt.operator_token = cairn::random_hex_token();
  if (!opt.operator_token.empty()) base_cmd.insert(base_cmd.end(), {"--operator-token", opt.operator_token});
  if (opt.serve) base_cmd.push_back("--serve");
  if (opt.ros2) base_cmd.push_back("--ros2");
  if (lab) base_cmd.insert(base_cmd.end(), {"--no-shm", "--bind", "0.0.0.0", "--peer", lab->robots_side_address()});
  if (lab && opt.link.rate_kbit > 0) base_cmd.push_back("--slow-link");
  base_cmd = secured(base_cmd, "base");

  std::cout << "Cairn mission '" << wf.world.name << "': " << robots << " robots, " << wf.world.objects.size()
            << " objects of interest, DDS domain " << opt.domain
            << (opt.secure ? ", DDS Security on (PKI-DH, AES-GCM)" : "") << "\n"
            << "console: http://" << console_host << ":" << opt.port << "/  (operator, with commands: http://"
            << console_host << ":" << opt.port << "/#token=" << opt.operator_token << ")\n";
  if (lab) std::cout << lab->describe() << "\n";
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const auto wall_start = std::chrono::steady_clock::now();
  std::vector<std::unique_ptr<ChildProcess>> procs;
  procs.push_back(std::make_unique<ChildProcess>("base", base_cmd, (out / "logs/base.log").string()));
  if (!opt.record.empty()) {
    // The recorder sits with the base. Behind an emulated radio it records what crosses the radio
    // (the shared topics): subscribing to the sensor topics would drag them over the link.
    std::vector<std::string> cmd = lab ? lab->prefix() : std::vector<std::string>{};
    cmd.insert(cmd.end(), {(bin / "cairn_record").string(), "--domain", std::to_string(opt.domain), "--robots",
                           std::to_string(robots), "--out", opt.record});
    if (opt.ros2) cmd.push_back("--ros2");
    if (lab)
      cmd.insert(cmd.end(), {"--peer", lab->robots_side_address(), "--topics", "cairn/mission_clock", "cairn/keyframe",
                             "cairn/object", "cairn/status", "cairn/ack", "cairn/correction", "cairn/goal",
                             "cairn/operator_command", "cairn/keep_out"});
    procs.push_back(
        std::make_unique<ChildProcess>("record", secured(cmd, "recorder"), (out / "logs/record.log").string()));
  }
  for (const auto& r : wf.world.robots) {
    const std::string id = std::to_string(r.id.value);
    procs.push_back(std::make_unique<ChildProcess>(
        "agent" + id,
        [&] {
          // Each robot's outbox lives with this mission's logs (removed at the start of a mission).
          std::vector<std::string> cmd{(bin / "cairn_agent").string(),
                                       "--robot",
                                       id,
                                       "--domain",
                                       std::to_string(opt.domain),
                                       "--outbox",
                                       (out / ("logs/outbox_robot" + id + ".sqlite")).string()};
          cmd.insert(cmd.end(), agent_extra.begin(), agent_extra.end());
          return secured(cmd, "robot" + id);
        }(),
        (out / ("logs/agent" + id + ".log")).string()));
  }
  procs.push_back(std::make_unique<ChildProcess>("sim",
                                                 secured(
                                                     [&] {
                                                       std::vector<std::string> cmd{(bin / "cairn_sim").string(),
                                                                                    "--world",
                                                                                    opt.world,
                                                                                    "--out",
                                                                                    (out / "ground_truth").string(),
                                                                                    "--domain",
                                                                                    std::to_string(opt.domain),
                                                                                    "--speed",
                                                                                    std::to_string(opt.speed)};
                                                       if (!opt.routes.empty())
                                                         cmd.insert(cmd.end(), {"--routes", opt.routes});
                                                       if (opt.radio_model)
                                                         cmd.insert(cmd.end(), {"--radio", radio_csv.string()});
                                                       // The recorder subscribes too (not behind a radio).
                                                       if (!opt.record.empty() && !lab)
                                                         cmd.insert(cmd.end(), {"--subscribers", "2"});
                                                       return cmd;
                                                     }(),
                                                     "sim"),
                                                 (out / "logs/sim.log").string()));
  for (const auto& p : procs) {
    if (!p->started()) {
      std::cerr << "cairn_mission: cannot start " << p->name() << "\n";
      return 3;
    }
  }

  cairn::mission::ProgressPoller progress(console_host, opt.port, robots);
  bool link_cut = false;
  // The simulated radio: the simulator says where each robot is out of range, this cuts its agent.
  cairn::mission::RadioFollower radio(radio_csv.string(), [&](int robot, bool cut_link, std::string* error) {
    for (const auto& p : procs) {
      if (p->name() == "agent" + std::to_string(robot)) return lab->set_process_cut(robot, p->pid(), cut_link, error);
    }
    *error = "no agent for robot " + std::to_string(robot);
    return false;
  });
  double progress_at_s = -1;
  const fs::path summary_file = out / "map" / "summary.json";
  while (true) {
    bool failed = false, workers_done = true;
    for (const auto& p : procs) {
      p->poll();
      if (p->exited() && p->exit_code() != 0) {
        std::cerr << "cairn_mission: " << p->name() << " failed (exit " << p->exit_code() << "); see " << p->log_path()
                  << "\n";
        failed = true;
      }
      if (p->name() != "base" && p->name() != "record") workers_done = workers_done && p->exited();
    }
    const bool base_done = procs[0]->exited() || (opt.serve && fs::exists(summary_file));
    if (failed || g_interrupted ||
        std::chrono::steady_clock::now() - wall_start > std::chrono::duration<double>(opt.timeout_s)) {
      if (!failed && !g_interrupted) std::cerr << "cairn_mission: timed out after " << opt.timeout_s << " s\n";
      for (const auto& p : procs) p->terminate();
      std::this_thread::sleep_for(std::chrono::seconds(1));
      return 1;
    }
    if (workers_done && base_done) break;
    if (lab && opt.link.cut_at_s >= 0) {
      const double t_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      const bool should_cut = t_s >= opt.link.cut_at_s && t_s < opt.link.cut_at_s + opt.link.cut_for_s;
      std::string error;
      if (should_cut != link_cut && lab->set_cut(should_cut, &error)) {
        link_cut = should_cut;
        std::cout << "[" << int(t_s) << " s] radio link " << (link_cut ? "cut" : "back") << std::endl;
      } else if (should_cut != link_cut) {
        std::cerr << "cairn_mission: " << error << "\n";
      }
    }
    std::optional<std::string> line;
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (opt.radio_model) {
      for (const std::string& change : radio.poll())
        std::cout << cairn::mission::wall_stamp(elapsed_s) << change << std::endl;
    }
    if (elapsed_s - progress_at_s >= 1.0) {  // progress once a second; the radio four times a second
      progress_at_s = elapsed_s;
      if (lab)
        lab->run_inside([&] { line = progress.changed_line(elapsed_s); });
      else
        line = progress.changed_line(elapsed_s);
    }
    if (line) std::cout << *line << std::endl;
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  for (const auto& p : procs) {
    if (p->name() != "record") continue;
    p->terminate();  // the recorder closes its file (summary, index) on SIGTERM
    for (int i = 0; i < 100 && !p->poll(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::cout << "recording: " << opt.record << " (" << p->log_path() << ")\n";
  }

  const auto link = lab ? std::optional<cairn::mission::LinkTraffic>(lab->traffic()) : std::nullopt;
  if (opt.radio_model && !cairn::mission::write_radio_map(wf.world, radio_csv.string(), (out / "ground_truth").string(),
                                                          (out / "radio.png").string()))
    std::cerr << "cairn_mission: cannot write " << (out / "radio.png") << "\n";
  int code = cairn::mission::report(out, wall_s, procs, link, std::cout);
  if (opt.serve && code == 0) {
    std::cout << "console still up at http://" << console_host << ":" << opt.port << "/#token=" << opt.operator_token
              << " (Ctrl-C to stop)" << std::endl;
    while (!g_interrupted && !procs[0]->poll()) std::this_thread::sleep_for(std::chrono::milliseconds(200));
    procs[0]->terminate();
    for (int i = 0; i < 50 && !procs[0]->poll(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return code;
}
