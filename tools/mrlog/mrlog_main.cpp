// cairn_mrlog: converts datasets into the Cairn multi-robot text log (docs/multirobot_log_format.md)
// and checks logs.
//   cairn_mrlog from-world --world worlds/office.yaml --routes worlds/routes/office.yaml --out office.mrlog
//                          [--robots 0 1] [--featureless]
//   cairn_mrlog from-carmen --out intel.mrlog --split 2 [--virtual-markers 4] intel.gfs.log
//   cairn_mrlog check file.mrlog
//   cairn_mrlog eval --log file.mrlog --results <cairn_base --out folder>   (needs TRUTH / MARKER)
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/errors.h"
#include "tools/mrlog/mrlog_convert.h"
#include "tools/mrlog/mrlog_eval.h"

namespace {

void print_summary(const cairn::MultiRobotLog& log) {
  for (const auto& [id, r] : log.robots) {
    std::set<int> ids;
    for (const auto& o : r.landmarks) ids.insert(o.id.value);
    std::printf("robot %d: %zu odometry, %zu scans, %zu landmark observations of %zu markers, %zu reference poses\n",
                id.value, r.odometry.size(), r.scans.size(), r.landmarks.size(), ids.size(), r.truth.size());
  }
  std::printf("%zu reference markers; %d NaN and %d inf beams\n", log.markers.size(), log.stats.nan_ranges,
              log.stats.inf_ranges);
}

int write(const cairn::MultiRobotLog& log, const std::string& path, const std::string& comment) {
  if (!cairn::write_multirobot_log_file(path, log, comment)) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    return 1;
  }
  print_summary(log);
  std::printf("wrote %s\n", path.c_str());
  return 0;
}

/// Errors of the base's results against the log's reference, in the base's own global frame
/// (mrlog_eval.h: a given start's frame, else the anchor robot's start), so no alignment is applied.
int evaluate(const cairn::MultiRobotLog& log, const std::string& dir) {
  if (log.robots.empty() || log.robots.begin()->second.truth.empty()) {
    std::fprintf(stderr, "the log has no TRUTH records for its first robot: nothing to compare\n");
    return 2;
  }
  std::ifstream summary_in(dir + "/summary.json");
  const nlohmann::json summary = summary_in ? nlohmann::json::parse(summary_in, nullptr, false) : nlohmann::json();
  const auto frame = cairn::mrlog::global_frame_of(log, summary);
  if (!frame) {
    std::fprintf(stderr, "no TRUTH records for the robot that fixes the global frame\n");
    return 2;
  }
  const cairn::SE2 T_global_world = frame->T_global_world;
  std::printf("global frame: %s\n", frame->description.c_str());
  cairn::TrajectoryErrorOptions no_align;
  no_align.align = false;
  for (const auto& [id, r] : log.robots) {
    const std::string path = dir + "/trajectory_robot" + std::to_string(id.value) + ".csv";
    if (r.truth.empty() || !std::ifstream(path)) {
      std::printf("robot %d: not placed (no %s) or no reference\n", id.value, path.c_str());
      continue;
    }
    cairn::Trajectory reference;
    for (const auto& t : r.truth) reference.push_back({t.stamp_ns, T_global_world * t.pose});
    const auto e = cairn::trajectory_error(cairn::read_trajectory_csv(path), reference, no_align);
    if (e)
      std::printf("robot %d: %d keyframes, global ATE rmse %.3f m, max %.3f m\n", id.value, e->matched, e->ate_rmse_m,
                  e->ate_max_m);
  }
  if (!summary.is_object() || !summary.contains("landmarks")) return 0;
  double worst = 0, sum2 = 0;
  int n = 0;
  for (const auto& l : summary["landmarks"]) {
    auto it = log.markers.find(cairn::LandmarkId(l["id"].get<int>()));
    if (it == log.markers.end()) continue;
    const double err =
        (Eigen::Vector2d(l["x_m"].get<double>(), l["y_m"].get<double>()) - T_global_world * it->second).norm();
    worst = std::max(worst, err);
    sum2 += err * err;
    ++n;
  }
  if (n > 0) std::printf("markers: %d placed, position error rmse %.3f m, max %.3f m\n", n, std::sqrt(sum2 / n), worst);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn multi-robot log converter"};
  app.require_subcommand(1);
  std::string out, world_path, routes_path;
  cairn::mrlog::WorldRecordOptions wo;
  auto* world = app.add_subcommand("from-world", "record a simulated world (odometry, scans, markers = its objects)");
  world->add_option("--world", world_path, "world YAML")->required()->check(CLI::ExistingFile);
  world->add_option("--routes", routes_path, "scripted routes YAML (default: the world file's own waypoints)");
  world->add_option("--out", out, "output .mrlog")->required();
  world->add_option("--robots", wo.robots, "robot ids to record (default: all)");
  world->add_option("--duration", wo.duration_s, "seconds (default: the world file's)");
  world->add_flag("--featureless", wo.featureless, "blank every scan: only markers can link the robots");
  world->add_option("--landmark-range", wo.landmarks.max_range_m, "marker detection range, m");
  world->add_option("--landmark-fov", wo.landmarks.fov_rad, "marker detection field of view, rad");
  world->add_option("--landmark-rate", wo.landmarks.rate_hz, "marker observations per second");
  world->add_option("--seed", wo.landmarks.seed, "marker noise seed");

  std::vector<std::string> inputs;
  cairn::mrlog::CarmenConvertOptions co;
  auto* carmen = app.add_subcommand("from-carmen", "CARMEN log(s) -> one robot per log, or one log split into robots");
  carmen->add_option("logs", inputs, "CARMEN logs (.clf/.log, plain or .gz)")->required()->check(CLI::ExistingFile);
  carmen->add_option("--out", out, "output .mrlog")->required();
  carmen->add_option("--split", co.split, "cut the one input log into this many robots")->check(CLI::Range(1, 64));
  carmen->add_option("--virtual-markers", co.virtual_marker_spacing_m,
                     "corrected logs: a marker every this many metres along the reference path");
  carmen->add_option("--landmark-range", co.landmarks.max_range_m, "virtual marker detection range, m");
  carmen->add_option("--seed", co.odometry_noise_seed, "odometry noise seed (corrected logs)");

  std::string check_path;
  auto* check = app.add_subcommand("check", "read a multi-robot log and print what it holds");
  check->add_option("log", check_path)->required();
  std::string eval_log, results;
  auto* eval = app.add_subcommand("eval", "compare cairn_base results with the log's TRUTH and MARKER records");
  eval->add_option("--log", eval_log)->required();
  eval->add_option("--results", results, "cairn_base --out folder")->required();
  CLI11_PARSE(app, argc, argv);

  try {
    if (world->parsed()) {
      cairn::sim::WorldLoadOptions load;
      load.routes_path = routes_path;
      const cairn::sim::WorldFile wf = cairn::sim::load_world_file(world_path, load);
      const auto log = cairn::mrlog::record_world(wf, wo);
      return write(log, out, "from world " + world_path + (wo.featureless ? " (featureless scans)" : ""));
    }
    if (carmen->parsed()) {
      std::vector<cairn::CarmenLog> logs;
      std::vector<bool> corrected;
      for (const std::string& p : inputs) {
        logs.push_back(cairn::read_carmen_log(p));
        corrected.push_back(cairn::is_corrected_log_name(p));
      }
      std::string comment = "from CARMEN";
      for (const std::string& p : inputs) comment += " " + p;
      if (co.split > 1) comment += ", split into " + std::to_string(co.split) + " robots";
      return write(cairn::mrlog::convert_carmen(logs, corrected, co), out, comment);
    }
    if (eval->parsed()) return evaluate(cairn::read_multirobot_log(eval_log), results);
    print_summary(cairn::read_multirobot_log(check_path));
    return 0;
  } catch (const cairn::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
