#include "tools/mission/mission_report.h"

// Eigen-using headers first: httplib pulls in <resolv.h>, whose `_res` macro breaks Eigen.
#include "common/errors.h"
#include "common/trajectory.h"
#include "tools/eval/mission_eval.h"
#include "tools/mission/exploration_report.h"
#include "tools/mission/radio_follower.h"

#include <httplib.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace cairn::mission {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::optional<json> get_json(httplib::Client& cli, const char* path) {
  auto res = cli.Get(path);
  if (!res || res->status != 200) return std::nullopt;
  auto j = json::parse(res->body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return std::nullopt;
  return j;
}

double simulated_time_s(const fs::path& gt_dir) {
  double t = 0;
  for (const auto& entry : fs::directory_iterator(gt_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("gt_robot", 0) == 0 && name != "gt_robots.csv") {
      const Trajectory tr = read_trajectory_csv(entry.path().string());
      if (!tr.empty()) t = std::max(t, ns_to_sec(tr.back().stamp_ns));
    }
  }
  return t;
}

}  // namespace

std::string wall_stamp(double wall_s) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << "[" << std::setw(6) << wall_s << " s] ";
  return s.str();
}

std::string ProgressPoller::line(double wall_s) const {
  std::ostringstream s;
  s << wall_stamp(wall_s) << std::fixed << std::setprecision(1);
  httplib::Client cli(host_, port_);
  cli.set_connection_timeout(0, 300'000);
  cli.set_read_timeout(1, 0);
  const auto status = get_json(cli, "/api/status");
  const auto robots = get_json(cli, "/api/robots");
  if (!status || !robots) {
    s << "waiting for the base station console";
    return s.str();
  }
  s << "mission t=" << status->value("mission_time_s", 0.0) << " s | linked " << status->value("linked_robots", 0)
    << "/" << status->value("robots", 0) << " | keyframes";
  const json list = robots->is_array() ? *robots : robots->value("robots", json::array());
  for (const auto& r : list) s << " r" << r.value("id", -1) << "=" << r.value("keyframes", 0);
  s << " | objects " << status->value("objects", 0) << " | mapped " << status->value("mapped_area_m2", 0.0) << " m2";
  return s.str();
}

std::optional<std::string> ProgressPoller::changed_line(double wall_s) {
  std::string l = line(wall_s);
  const size_t state = l.find("] ");  // after the wall time
  const std::string now = state == std::string::npos ? l : l.substr(state + 2);
  if (now == last_state_) return std::nullopt;
  last_state_ = now;
  return l;
}

namespace {

json to_json(const LinkDirection& d) {
  return {{"packets", d.packets},
          {"bytes", d.bytes},
          {"lost_packets", d.lost_packets},
          {"lost_bytes", d.lost_bytes},
          {"queue_dropped_packets", d.queue_dropped_packets}};
}

/// The radio's share of the summary: what crossed it each way and what it cost over the payload.
void report_link(const LinkTraffic& link, double payload_bytes, json* results, std::ostream& s) {
  auto line = [&](const char* way, const LinkDirection& d) {
    s << "  " << way << ": " << double(d.bytes + d.lost_bytes) / 1024.0 << " KiB in " << d.packets + d.lost_packets
      << " packets (" << d.lost_packets << " lost on the air, " << d.queue_dropped_packets
      << " dropped by the rate limit's queue)\n";
  };
  s << "radio link:\n";
  line("robots -> base", link.to_base);
  line("base -> robots", link.to_robots);
  const double offered = double(link.to_base.bytes + link.to_base.lost_bytes);
  const double overhead = payload_bytes > 0 ? offered / payload_bytes : 0.0;
  s << "  overhead: " << overhead << " x the robots' payload (" << payload_bytes / 1024.0
    << " KiB of keyframes and objects)\n";
  (*results)["radio"] = {{"to_base", to_json(link.to_base)},
                         {"to_robots", to_json(link.to_robots)},
                         {"payload_bytes", payload_bytes},
                         {"overhead", overhead}};
}

/// The simulated radio's share (logs/radio.csv, written with --radio-model): how often and how long
/// each robot was out of range of the team's antennas.
void report_radio_model(const fs::path& csv_path, const std::map<int, uint64_t>& dropped, json* results,
                        std::ostream& s) {
  std::ifstream csv(csv_path);
  if (!csv) return;
  json links = json::array();
  s << "radio model (walls and distance):\n";
  for (const RadioLinkSummary& r : summarize_radio(csv)) {
    s << "  robot " << r.robot << ": ";
    if (r.cuts == 0)
      s << "always in range";
    else
      s << "out of range " << r.cuts << " time(s), " << r.out_of_range_s << " s in all, first at " << r.first_cut_s
        << " s";
    const auto it = dropped.find(r.robot);
    const uint64_t packets = it == dropped.end() ? 0 : it->second;
    s << " (weakest " << r.lowest_dbm << " dBm; " << packets << " packets dropped out of range)\n";
    links.push_back({{"robot", r.robot},
                     {"cuts", r.cuts},
                     {"out_of_range_s", r.out_of_range_s},
                     {"first_cut_s", r.first_cut_s},
                     {"lowest_dbm", r.lowest_dbm},
                     {"dropped_packets", packets}});
  }
  (*results)["radio_model"] = links;
}

}  // namespace

int report(const fs::path& out, double wall_s, const std::vector<std::unique_ptr<ChildProcess>>& procs,
           const std::optional<LinkTraffic>& link, std::ostream& os) {
  json results;
  eval::MissionScore score;
  json summary;
  double sim_s = 0;
  try {
    score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
    sim_s = simulated_time_s(out / "ground_truth");
    std::ifstream in(out / "map" / "summary.json");
    if (!in) throw InputError((out / "map" / "summary.json").string() + ": cannot open file");
    summary = json::parse(in, nullptr, false);
    if (summary.is_discarded()) throw InputError((out / "map" / "summary.json").string() + ": malformed JSON");
  } catch (const InputError& e) {
    os << "cairn_mission: cannot score the mission: " << e.what() << "\n";
    return 4;
  }
  std::ostringstream s;
  s << std::fixed << std::setprecision(2);
  s << "\n=== Mission summary ===\n";
  s << "simulated " << sim_s << " s in " << wall_s << " s wall (" << (wall_s > 0 ? sim_s / wall_s : 0)
    << "x real time)\n";
  s << "mapped area " << summary.value("mapped_area_m2", 0.0) << " m2, " << summary.value("objects", 0)
    << " objects on the map\n";
  results["simulated_s"] = sim_s;
  results["wall_s"] = wall_s;
  results["mapped_area_m2"] = summary.value("mapped_area_m2", 0.0);
  results["robots"] = json::array();
  for (const auto& r : summary.value("robots", json::array())) {
    const json link = r.value("link", json::object());
    const int kf = r.value("keyframes", 0);
    const double kf_bytes = link.value("keyframe_bytes", 0.0), obj_bytes = link.value("object_bytes", 0.0);
    const int obj_msgs = link.value("object_messages", 0);
    const bool linked = r.value("linked", false);
    const json time_to_link = r.value("time_to_link_s", json());
    std::ostringstream linked_text;
    linked_text << std::fixed << std::setprecision(1);
    if (!linked) {
      linked_text << " (NOT LINKED to the map)";
    } else if (time_to_link.is_number()) {
      linked_text << " (linked " << time_to_link.get<double>() << " s after its first keyframe)";
    }
    s << "robot " << r.value("id", -1) << linked_text.str() << ": " << kf << " keyframes (" << (kf ? kf_bytes / kf : 0)
      << " B each), " << obj_msgs << " object messages (" << (obj_msgs ? obj_bytes / obj_msgs : 0) << " B each), "
      << (kf_bytes + obj_bytes) / 1024.0 << " KiB sent\n";
    results["robots"].push_back({{"id", r.value("id", -1)},
                                 {"linked", linked},
                                 {"time_to_link_s", time_to_link},
                                 {"keyframes", kf},
                                 {"inter_robot_closures", r.value("inter_robot_closures", 0)},
                                 {"keyframe_bytes", kf_bytes},
                                 {"object_messages", obj_msgs},
                                 {"object_bytes", obj_bytes}});
  }
  if (link) {
    double payload_bytes = 0;
    for (const auto& r : results["robots"])
      payload_bytes += r.value("keyframe_bytes", 0.0) + r.value("object_bytes", 0.0);
    report_link(*link, payload_bytes, &results, s);
    report_radio_model(out / "logs" / "radio.csv", link->out_of_range_packets, &results, s);
  }
  // Loud, never quiet: robots the base could not place, and what they found, in their own frames.
  const json unlinked = summary.value("unlinked_robots", json::array());
  const json unplaced = summary.value("unplaced_objects", json::array());
  results["unlinked_robots"] = unlinked;
  results["unplaced_objects"] = unplaced;
  if (!unlinked.empty()) {
    s << "!! NOT ON THE MAP: robot(s) " << unlinked.dump() << " were never linked to the others; " << unplaced.size()
      << " find(s) are only in their own frame (robot<N>_own_frame.png in map/):\n";
    for (const json& o : unplaced) {
      s << "!!   " << o.value("class", std::string("object")) << " " << o.value("id", std::string("?")) << ": "
        << o.value("from_entry", json::object()).value("text", std::string("position unknown")) << "\n";
    }
  }
  s << "accuracy against ground truth:\n" << eval::format_score(score);
  if (score.coverage) {
    int victims = 0;
    for (const auto& c : score.classes) victims += c.class_name == "victim" ? c.ground_truth : 0;
    const ExplorationFigures f = exploration_figures(summary.value("coverage_series", json::array()),
                                                     score.coverage->fraction(), victims, sim_s);
    auto at = [](const std::optional<double>& t) { return t ? json(*t) : json(); };
    auto text = [](const std::optional<double>& t) {
      return t ? std::to_string(int(*t)) + " s" : std::string("never");
    };
    const json exploration = summary.value("exploration", json::object());
    // What the simulator saw the robots do (gt_motion.csv: id, distance_m, collisions).
    double driven_m = 0;
    int collisions = 0;
    std::ifstream motion(out / "ground_truth" / "gt_motion.csv");
    std::string line;
    std::getline(motion, line);  // header
    while (std::getline(motion, line)) {
      int id = 0, hits = 0;
      double d = 0;
      if (std::sscanf(line.c_str(), "%d,%lf,%d", &id, &d, &hits) == 3) driven_m += d, collisions += hits;
    }
    results["exploration"] = {{"coverage_per_second", f.per_second},
                              {"t50_s", at(f.t50_s)},
                              {"t90_s", at(f.t90_s)},
                              {"t99_s", at(f.t99_s)},
                              {"all_victims_s", at(f.all_victims_s)},
                              {"goals_blacklisted", exploration.value("goals_blacklisted", 0)},
                              {"distance_driven_m", driven_m},
                              {"collisions", collisions},
                              {"sent_home", exploration.contains("sent_home_at_s")},
                              {"sent_home_at_s", exploration.value("sent_home_at_s", json())}};
    s << "exploration: 50 % covered at " << text(f.t50_s) << ", 90 % at " << text(f.t90_s) << ", 99 % at "
      << text(f.t99_s) << "; every victim on the map at " << text(f.all_victims_s) << "; "
      << exploration.value("goals_blacklisted", 0) << " goal(s) blacklisted; " << int(driven_m) << " m driven, "
      << collisions << " collision(s) (coverage.png)\n";
    if (!write_coverage_plot({{"this mission", f.per_second}}, victims, "Mission " + out.filename().string(),
                             (out / "coverage.png").string())) {
      s << "!! could not write " << (out / "coverage.png").string() << "\n";
    }
  }
  s << "peak memory:";
  json memory = json::object();
  for (const auto& p : procs) {
    s << " " << p->name() << " " << p->peak_rss_kb() / 1024 << " MiB";
    memory[p->name()] = p->peak_rss_kb();
  }
  s << "\ncpu time:";
  json cpu = json::object();
  for (const auto& p : procs) {
    char buf[32];
    std::snprintf(buf, sizeof buf, " %.1f s", p->cpu_s());
    s << " " << p->name() << buf;
    cpu[p->name()] = p->cpu_s();
  }
  results["cpu_s"] = cpu;
  s << "\nresults: " << fs::absolute(out).string() << " (map.png, map.pgm/.yaml, objects.geojson, *.ply, "
    << "objects.bt, graph.g2o in map/; logs in logs/)\n";
  results["peak_rss_kb"] = memory;
  results["evaluation"] = eval::to_json(score);
  // One line that says how it went, last.
  const int robot_count = int(score.robots.size());
  const int placed = robot_count - int(unlinked.size());
  double worst_rmse_m = 0;
  for (const auto& r : score.robots) {
    if (r.global) worst_rmse_m = std::max(worst_rmse_m, r.global->ate_rmse_m);
  }
  std::ostringstream verdict;
  verdict << std::fixed << std::setprecision(2);
  if (unlinked.empty()) {
    verdict << "Verdict: mission mapped: all " << robot_count << " robots on one map (worst " << worst_rmse_m
            << " m RMSE), " << score.objects.matched << "/" << score.objects.ground_truth << " objects found";
  } else {
    verdict << "Verdict: INCOMPLETE: " << placed << "/" << robot_count << " robots on the map, " << unplaced.size()
            << " find(s) only in an unplaced robot's own frame, " << score.objects.matched << "/"
            << score.objects.ground_truth << " objects on the map";
  }
  s << verdict.str() << "\n";
  results["verdict"] = verdict.str();
  std::ofstream(out / "results.json") << results.dump(2) << "\n";
  std::ofstream(out / "summary.txt") << s.str();
  os << s.str();
  return 0;
}

}  // namespace cairn::mission
