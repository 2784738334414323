// cairn_slam_eval: ATE (after best SE2 alignment) and RPE of a trajectory CSV against a corrected
// CARMEN log (matched to a raw log by identical scans with --raw-log) or against a trajectory CSV
// (--reference-csv, e.g. a simulated robot's truth.csv from cairn_slam --mrlog), and the Kuemmerle et al.
// relations metric with --relations, and with --scan-checks the reference-free checks of
// reference_checks.h for both the reference and the estimate.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>

#include "common/errors.h"
#include "tools/slam/reference_checks.h"
#include "tools/slam/slam_eval.h"

namespace {

// Per-pose error of the aligned estimate against the reference (both at the reference's stamps).
void write_errors_csv(const std::string& path, const cairn::Trajectory& est, const cairn::Trajectory& ref,
                      const cairn::SE2& T_reference_estimate) {
  std::ofstream out(path);
  if (!out) throw cairn::InputError("cannot write --errors-csv " + path);
  out << "stamp_ns,ref_x_m,ref_y_m,est_x_m,est_y_m,error_m,yaw_error_deg\n";
  size_t j = 0;
  for (const auto& e : est) {
    while (j < ref.size() && ref[j].stamp_ns < e.stamp_ns) ++j;
    if (j == ref.size() || ref[j].stamp_ns != e.stamp_ns) continue;
    const cairn::SE2 a = T_reference_estimate * e.pose;
    const cairn::SE2& r = ref[j].pose;
    out << e.stamp_ns << ',' << r.x() << ',' << r.y() << ',' << a.x() << ',' << a.y() << ','
        << (a.translation() - r.translation()).norm() << ',' << cairn::normalize_angle(a.yaw() - r.yaw()) * 180.0 / M_PI
        << '\n';
  }
}

nlohmann::json consistency_json(const cairn::slam::RevisitConsistency& c) {
  return {{"points", c.points},
          {"revisit_fraction", c.revisit_fraction},
          {"mean_nn_m", c.mean_nn_m},
          {"median_nn_m", c.median_nn_m},
          {"within_5cm_fraction", c.within_close_fraction}};
}

nlohmann::json scan_checks_json(const cairn::slam::ScanChecks& c) {
  const auto& f = c.forward;
  return {{"poses", c.poses},
          {"revisit_consistency",
           {{"reference", consistency_json(c.reference)}, {"estimate", consistency_json(c.estimate)}}},
          {"forward_range",
           {{"pairs", f.pairs},
            {"laser_forward_m", f.laser_forward_m},
            {"reference",
             {{"forward_m", f.trajectory_forward_m[0]},
              {"ratio", f.ratio[0]},
              {"median_difference_m", f.median_difference_m[0]}}},
            {"estimate",
             {{"forward_m", f.trajectory_forward_m[1]},
              {"ratio", f.ratio[1]},
              {"median_difference_m", f.median_difference_m[1]}}}}},
          {"affine_estimate_to_reference",
           {{"rmse_m", c.affine.rmse_m},
            {"scale_major", c.affine.scale_major},
            {"scale_minor", c.affine.scale_minor},
            {"major_axis_deg", c.affine.major_axis_deg}}}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn 2D SLAM accuracy evaluation"};
  std::string estimate_path, reference_path, reference_csv_path, raw_path, relations_path, errors_path;
  double offset_s = std::numeric_limits<double>::quiet_NaN();
  app.add_option("--estimate", estimate_path, "trajectory CSV (stamp_ns,x_m,y_m,yaw_rad)")->required();
  auto* reference_option = app.add_option("--reference", reference_path, "corrected CARMEN log (reference poses)");
  app.add_option("--reference-csv", reference_csv_path,
                 "reference trajectory CSV (e.g. cairn_slam --mrlog's truth.csv)")
      ->excludes(reference_option);
  app.add_option("--raw-log", raw_path, "raw log the estimate was computed from (match scans by ranges)");
  app.add_option("--relations", relations_path, "Kuemmerle .relations file");
  app.add_option("--relations-offset-s", offset_s, "relation stamp - log stamp (default: estimated)");
  app.add_option("--errors-csv", errors_path,
                 "write the per-pose error after alignment (stamp_ns,ref_x_m,ref_y_m,est_x_m,est_y_m,error_m,"
                 "yaw_error_deg)");
  bool scan_checks = false;
  app.add_flag("--scan-checks", scan_checks,
               "also judge reference and estimate against the reference log's scans: revisit consistency, "
               "forward motion vs range to the wall ahead, affine fit (reference_checks.h)");
  CLI11_PARSE(app, argc, argv);
  if (scan_checks && reference_path.empty()) {
    std::cerr << "cairn_slam_eval: --scan-checks needs --reference (the corrected log's scans)\n";
    return 2;
  }
  nlohmann::json j;
  try {
    const cairn::Trajectory estimate = cairn::read_trajectory_csv(estimate_path);
    if (!reference_path.empty() || !reference_csv_path.empty()) {
      cairn::CarmenLog corrected;
      int unmatched = 0;
      std::vector<size_t> scan_index;
      cairn::Trajectory ref;
      if (!reference_csv_path.empty()) {
        ref = cairn::read_trajectory_csv(reference_csv_path);
      } else {
        corrected = cairn::read_carmen_log(reference_path);
        cairn::CarmenLog raw;
        if (!raw_path.empty()) raw = cairn::read_carmen_log(raw_path);
        ref = cairn::slam::reference_from_corrected(corrected, raw_path.empty() ? nullptr : &raw, &unmatched,
                                                    &scan_index);
      }
      const cairn::Trajectory est = cairn::slam::sample_at(estimate, ref, cairn::kNsPerSec);
      const auto e = cairn::trajectory_error(est, ref);
      if (!e) throw cairn::InputError("fewer than 2 estimate poses match the reference");
      if (!errors_path.empty()) write_errors_csv(errors_path, est, ref, e->T_reference_estimate);
      j["reference_poses"] = ref.size();
      j["reference_unmatched_scans"] = unmatched;
      j["matched"] = e->matched;
      j["ate_rmse_m"] = e->ate_rmse_m;
      j["ate_mean_m"] = e->ate_mean_m;
      j["ate_max_m"] = e->ate_max_m;
      j["rpe_trans_mean_m"] = e->rpe_trans_mean_m;
      j["rpe_rot_mean_deg"] = e->rpe_rot_mean_rad * 180.0 / M_PI;
      if (scan_checks) j["scan_checks"] = scan_checks_json(cairn::slam::scan_checks(corrected, ref, scan_index, est));
    }
    if (!relations_path.empty()) {
      const auto relations = cairn::slam::read_relations(relations_path);
      if (std::isnan(offset_s)) offset_s = cairn::slam::estimate_time_offset_s(relations, estimate);
      const auto r = cairn::slam::relations_error(relations, estimate, offset_s);
      j["relations"] = {{"offset_s", offset_s},       {"used", r.used},
                        {"total", r.total},           {"trans_mean_m", r.trans_mean_m},
                        {"trans_sd_m", r.trans_sd_m}, {"rot_mean_deg", r.rot_mean_deg},
                        {"rot_sd_deg", r.rot_sd_deg}};
    }
  } catch (const cairn::InputError& e) {
    std::cerr << "cairn_slam_eval: " << e.what() << "\n";
    return 2;
  }
  std::cout << j.dump(2) << "\n";
  return 0;
}
