// cairn_slam: runs the robot agent's 2D SLAM over a CARMEN log, or over one robot of a Cairn
// multi-robot log (a recorded simulated world: its TRUTH poses are exact, written as truth.csv), as
// fast as it can and writes the trajectory (CSV), the map (PGM + YAML and PNG) and run statistics
// (JSON) into --out.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "common/errors.h"
#include "common/huge_pages.h"
#include "tools/slam/slam_runner.h"

namespace {

nlohmann::json stats_json(const cairn::slam::SlamRunStats& s, double total_wall_s, double total_cpu_s) {
  return {{"scans", s.scans},
          {"matched", s.matched},
          {"motion_filtered", s.motion_filtered},
          {"match_failed", s.match_failed},
          {"too_few_points", s.too_few_points},
          {"odometry_stalled", s.odometry_stalled},
          {"nodes", s.nodes},
          {"submaps", s.submaps},
          {"loop_closures", s.loop_closures},
          {"loop_searches", s.loop_searches},
          {"anisotropic_loop_closures", s.anisotropic_loop_closures},
          {"anisotropic_local_nodes", s.anisotropic_local_nodes},
          {"optimizations", s.optimizations},
          {"loop_scored_candidates", s.loop_scored_candidates},
          {"loop_scored_candidates_failed", s.loop_scored_candidates_failed},
          {"loop_matcher_mb", s.loop_matcher_mb},
          {"beams",
           {{"valid", s.beams.valid},
            {"nan_or_inf", s.beams.nan_or_inf},
            {"too_close", s.beams.too_close},
            {"max_range", s.beams.max_range}}},
          {"log_duration_s", s.log_duration_s},
          {"slam_wall_s", s.slam_wall_s},
          {"slam_cpu_s", s.slam_cpu_s},
          {"slam_sys_cpu_s", s.slam_sys_cpu_s},
          {"slam_minor_faults", s.slam_minor_faults},
          {"slam_major_faults", s.slam_major_faults},
          {"scans_per_s", s.scans_per_s()},
          {"real_time_factor", s.real_time_factor()},
          {"scans_per_cpu_s", s.slam_cpu_s > 0 ? s.scans / s.slam_cpu_s : 0.0},
          {"real_time_factor_cpu", s.slam_cpu_s > 0 ? s.log_duration_s / s.slam_cpu_s : 0.0},
          {"total_wall_s", total_wall_s},
          {"total_cpu_s", total_cpu_s},
          {"peak_rss_mb", cairn::slam::peak_rss_mb()}};
}

bool write_png(const std::string& path, const cairn::OccupancyGrid& grid) {
  const std::vector<uint8_t> pixels = grid.to_image();
  if (pixels.empty()) return false;
  const cv::Mat image(grid.height(), grid.width(), CV_8UC1, const_cast<uint8_t*>(pixels.data()));
  return cv::imwrite(path, image);
}

}  // namespace

int main(int argc, char** argv) {
  cairn::reexec_with_huge_pages(argv);  // common/huge_pages.h
  CLI::App app{"Cairn offline 2D SLAM over a CARMEN log or one robot of a multi-robot log"};
  std::string log_path, mrlog_path, out_dir, corrected_mode = "auto";
  int robot = 0;
  cairn::slam::SlamRunOptions options;
  double rot_deg_per_m = options.noise.rotation_noise_rad_per_m * 180.0 / M_PI;
  bool no_loop_closure = false, no_map = false;
  auto* log_option = app.add_option("--log", log_path, "CARMEN log (plain or .gz)");
  auto* mrlog_option = app.add_option("--mrlog", mrlog_path,
                                      "Cairn multi-robot log (cairn_mrlog from-world): run --robot; its TRUTH "
                                      "poses go to truth.csv");
  log_option->excludes(mrlog_option);
  app.add_option("--robot", robot, "robot of --mrlog")->needs(mrlog_option);
  app.add_option("--out", out_dir, "output folder")->required();
  app.add_option("--corrected", corrected_mode, "auto|yes|no: the log's poses are a reference, not odometry")
      ->check(CLI::IsMember({"auto", "yes", "no"}));
  app.add_option("--noise-translation", options.noise.translation_noise_per_m, "corrected logs: sigma per metre");
  app.add_option("--noise-rotation-deg-per-m", rot_deg_per_m, "corrected logs: yaw sigma, degrees per metre");
  app.add_option("--seed", options.noise.seed, "odometry noise seed");
  app.add_flag("--no-loop-closure", no_loop_closure, "local SLAM only");
  app.add_flag("--no-map", no_map, "skip writing the map");
  bool no_correlative = false;
  app.add_flag("--no-correlative", no_correlative, "local matching: Ceres only (from the prediction)");
  app.add_option("--scans-per-submap", options.slam.submaps.scans_per_submap, "local submap size");
  app.add_option("--ceres-translation-weight", options.slam.matcher.ceres.translation_weight, "local Ceres prior");
  app.add_option("--ceres-rotation-weight", options.slam.matcher.ceres.rotation_weight, "local Ceres prior");
  app.add_option("--loop-search-every-n", options.slam.loop_closure.search_every_n_nodes, "loop search node sampling");
  app.add_option("--optimize-every-n", options.slam.loop_closure.optimize_every_n_nodes, "pose graph period (nodes)");
  auto& lc = options.slam.loop_closure;
  app.add_option("--loop-anchor-gap-factor", lc.anchor_gap_factor,
                 "loop search window also bounded by this times the drift rate the optimisations corrected "
                 "times the travel since the last optimised loop closure (0: only by the nodes since the "
                 "submap was last touched)");
  app.add_option("--loop-tracking-max-gap", lc.tracking_max_gap_nodes,
                 "search near the submap's latest loop closure for nodes within this many nodes of it (0: off)");
  app.add_option("--loop-failure-backoff", lc.max_failure_backoff,
                 "a submap whose searches failed k times skips min(k, this) sampled nodes (0: off)");
  app.add_option(
      "--loop-covariance-weighting", lc.covariance_weighting,
      "loop closures weighted by their score-surface covariance (anisotropic along corridors; 0: fixed weights)");
  app.add_option("--loop-covariance-min-ratio", lc.covariance_min_weight_ratio,
                 "covariance weighting: weakest direction's weight, fraction of the fixed loop weight");
  app.add_option("--local-covariance-weighting", lc.local_covariance_weighting,
                 "local SLAM constraints (intra-submap, successive) weighted by the scan match's score-surface "
                 "covariance (0: fixed)");
  app.add_option("--local-covariance-min-ratio", lc.local_covariance_min_weight_ratio,
                 "local covariance weighting: weakest direction's weight, fraction of the fixed weight");
  app.add_option("--covariance-temperature", lc.score_surface.temperature,
                 "score-surface covariance: score drop (0..1) that lowers a shift's weight by e");
  app.add_option("--covariance-window", lc.score_surface.window_m, "score-surface covariance: +- shift window, m");
  app.add_option("--covariance-max-points", lc.score_surface.max_points, "score-surface covariance: points scored");
  app.add_option("--graph-periodic-iterations", lc.periodic_max_num_iterations, "periodic pose graph optimisations");
  app.add_option("--graph-final-iterations", lc.graph.max_num_iterations, "final pose graph optimisation");
  app.add_option("--local-ceres-iterations", options.slam.matcher.ceres.max_num_iterations, "local scan matcher");
  app.add_option("--loop-max-distance", lc.max_constraint_distance_m, "loop search: node to submap origin, m");
  app.add_option("--loop-min-search-score", lc.min_search_score, "branch-and-bound acceptance score");
  app.add_option("--loop-max-range-for-step", lc.fast.max_range_for_step_m,
                 "branch-and-bound angular step: one cell at this range, m");
  app.add_option("--loop-search-voxel", lc.search_voxel_m, "branch-and-bound point thinning, m");
  double correlative_angular_deg = options.slam.matcher.correlative.angular_window_rad * 180.0 / M_PI;
  app.add_option("--correlative-angular-window-deg", correlative_angular_deg, "local correlative search, +- deg");
  app.add_option("--correlative-linear-window", options.slam.matcher.correlative.linear_window_m,
                 "local correlative search, +- m");
  app.add_option("--correlative-max-range-for-step", options.slam.matcher.correlative.max_range_for_step_m,
                 "local correlative angular step: one cell at this range, m");
  app.add_option("--free-space-max-length", options.slam.submaps.inserter.max_free_space_length_m,
                 "submaps: free space inserted along at most this much of each beam, m (0: all)");
  app.add_option("--submap-initial-margin", options.slam.submaps.initial_margin_m,
                 "submaps: initial grid margin around the first scan, m");
  std::vector<int> dropout;
  app.add_option("--odometry-dropout", dropout,
                 "FIRST LAST: the odometry holds its reading before scan FIRST until scan LAST (robustness runs)")
      ->expected(2);
  app.add_option("--held-odometry-scan-change", options.slam.held_odometry_scan_change_m,
                 "odometry repeating its reading while the scan moved more than this (median beam, m) is held: the "
                 "scan is skipped (0: off)");
  app.add_option("--match-voxel", options.slam.match_voxel_m, "local matching point thinning, m");
  app.add_option("--max-ray-length", options.slam.submaps.inserter.max_ray_length_m,
                 "submaps: beams longer than this are cut (their endpoint is not a hit), m");
  app.add_option("--field-line-max-gap", options.slam.submaps.inserter.field_line_max_gap_m,
                 "submaps: likelihood field also along segments between consecutive hits closer than this, m (0: off)");
  app.add_option("--field-line-collinear", options.slam.submaps.inserter.field_line_collinear,
                 "submaps: field segments only where a neighbouring hit continues the line");
  app.add_option("--field-line-tolerance-ratio", options.slam.submaps.inserter.field_line_tolerance_ratio,
                 "submaps: collinearity tolerance, fraction of the gap");
  app.add_option("--field-sigma", options.slam.submaps.inserter.field_sigma_cells,
                 "submaps: likelihood field hit kernel sigma, cells");
  cairn::CarmenReadOptions read_options;
  app.add_option("--no-return-range", read_options.no_return_range_m,
                 "log readings at or beyond this are 'no return' (not a hit), m");
  CLI11_PARSE(app, argc, argv);
  if (log_path.empty() == mrlog_path.empty()) {
    std::cerr << "cairn_slam: give one of --log and --mrlog\n";
    return 2;
  }
  if (!dropout.empty()) {
    if (dropout[0] < 1 || dropout[1] < dropout[0]) {
      std::cerr << "cairn_slam: --odometry-dropout needs 1 <= FIRST <= LAST, got " << dropout[0] << " " << dropout[1]
                << "\n";
      return 2;
    }
    options.odometry_dropout_first = dropout[0];
    options.odometry_dropout_last = dropout[1];
  }
  options.slam.matcher.correlative.angular_window_rad = correlative_angular_deg * M_PI / 180.0;
  options.noise.rotation_noise_rad_per_m = rot_deg_per_m * M_PI / 180.0;
  options.slam.loop_closure.enabled = !no_loop_closure;
  options.slam.matcher.use_correlative = !no_correlative;
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = cairn::slam::process_cpu_s();
  cairn::CarmenLog log;
  cairn::Trajectory truth;
  try {
    if (!mrlog_path.empty()) {
      const cairn::MultiRobotLog mrlog = cairn::read_multirobot_log(mrlog_path);
      const cairn::RobotLogData* data = mrlog.robot(cairn::RobotId(robot));
      if (!data) throw cairn::InputError(mrlog_path + ": no robot " + std::to_string(robot));
      log = cairn::slam::carmen_log_from_robot(*data);
      truth = data->truth;
    } else {
      log = cairn::read_carmen_log(log_path, read_options);
    }
    if (log.scans.empty())
      throw cairn::InputError((mrlog_path.empty() ? log_path : mrlog_path) +
                              ": no laser scans in the log (FLASER, ROBOTLASER1 or SCAN records): nothing to map");
  } catch (const cairn::InputError& e) {
    std::cerr << "cairn_slam: " << e.what() << "\n";
    return 2;
  }
  // A multi-robot log's odometry is raw odometry.
  const bool corrected = !mrlog_path.empty()        ? false
                         : corrected_mode == "auto" ? cairn::is_corrected_log_name(log_path)
                                                    : corrected_mode == "yes";
  const cairn::slam::SlamRunResult r = cairn::slam::run_slam(log, corrected, options);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  bool ok = cairn::write_trajectory_csv(out_dir + "/trajectory.csv", r.trajectory) &&
            cairn::write_trajectory_csv(out_dir + "/odometry.csv", r.odometry) &&
            (truth.empty() || cairn::write_trajectory_csv(out_dir + "/truth.csv", truth));
  if (!no_map) {
    const cairn::OccupancyGrid map = cairn::slam::render_map(log, r.trajectory, options.map);
    ok = ok && map.write_pgm_yaml(out_dir + "/map") && write_png(out_dir + "/map.png", map);
  }
  const double total_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  nlohmann::json j = stats_json(r.stats, total_wall_s, cairn::slam::process_cpu_s() - cpu0);
  j["log"] = mrlog_path.empty() ? log_path : mrlog_path + " robot " + std::to_string(robot);
  j["corrected_log_with_synthetic_odometry"] = corrected;
  j["unknown_records"] = log.stats.unknown_records;
  std::ofstream(out_dir + "/stats.json") << j.dump(2) << "\n";
  if (!ok) {
    std::cerr << "cairn_slam: cannot write outputs into " << out_dir << "\n";
    return 1;
  }
  std::cout << j.dump(2) << "\n";
  return 0;
}
