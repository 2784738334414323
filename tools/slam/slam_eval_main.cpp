// cairn_slam_eval: ATE (after best SE2 alignment) and RPE of a trajectory CSV against a corrected
// CARMEN log (matched to a raw log by identical scans with --raw-log), and the Kuemmerle et al.
// relations metric with --relations.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <iostream>

#include "common/errors.h"
#include "tools/slam/slam_eval.h"

int main(int argc, char** argv) {
  CLI::App app{"Cairn 2D SLAM accuracy evaluation"};
  std::string estimate_path, reference_path, raw_path, relations_path;
  double offset_s = std::numeric_limits<double>::quiet_NaN();
  app.add_option("--estimate", estimate_path, "trajectory CSV (stamp_ns,x_m,y_m,yaw_rad)")->required();
  app.add_option("--reference", reference_path, "corrected CARMEN log (reference poses)");
  app.add_option("--raw-log", raw_path, "raw log the estimate was computed from (match scans by ranges)");
  app.add_option("--relations", relations_path, "Kuemmerle .relations file");
  app.add_option("--relations-offset-s", offset_s, "relation stamp - log stamp (default: estimated)");
  CLI11_PARSE(app, argc, argv);
  nlohmann::json j;
  try {
    const cairn::Trajectory estimate = cairn::read_trajectory_csv(estimate_path);
    if (!reference_path.empty()) {
      const cairn::CarmenLog corrected = cairn::read_carmen_log(reference_path);
      cairn::CarmenLog raw;
      if (!raw_path.empty()) raw = cairn::read_carmen_log(raw_path);
      int unmatched = 0;
      const cairn::Trajectory ref =
          cairn::slam::reference_from_corrected(corrected, raw_path.empty() ? nullptr : &raw, &unmatched);
      const cairn::Trajectory est = cairn::slam::sample_at(estimate, ref, cairn::kNsPerSec);
      const auto e = cairn::trajectory_error(est, ref);
      if (!e) throw cairn::InputError("fewer than 2 estimate poses match the reference");
      j["reference_poses"] = ref.size();
      j["reference_unmatched_scans"] = unmatched;
      j["matched"] = e->matched;
      j["ate_rmse_m"] = e->ate_rmse_m;
      j["ate_mean_m"] = e->ate_mean_m;
      j["ate_max_m"] = e->ate_max_m;
      j["rpe_trans_mean_m"] = e->rpe_trans_mean_m;
      j["rpe_rot_mean_deg"] = e->rpe_rot_mean_rad * 180.0 / M_PI;
    }
    if (!relations_path.empty()) {
      const auto relations = cairn::slam::read_relations(relations_path);
      if (std::isnan(offset_s)) offset_s = cairn::slam::estimate_time_offset_s(relations, estimate);
      const auto r = cairn::slam::relations_error(relations, estimate, offset_s);
      j["relations"] = {{"offset_s", offset_s}, {"used", r.used}, {"total", r.total},
                        {"trans_mean_m", r.trans_mean_m}, {"trans_sd_m", r.trans_sd_m},
                        {"rot_mean_deg", r.rot_mean_deg}, {"rot_sd_deg", r.rot_sd_deg}};
    }
  } catch (const cairn::InputError& e) {
    std::cerr << "cairn_slam_eval: " << e.what() << "\n";
    return 2;
  }
  std::cout << j.dump(2) << "\n";
  return 0;
}
