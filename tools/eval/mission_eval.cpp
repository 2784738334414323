#include "tools/eval/mission_eval.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common/errors.h"

namespace cairn::eval {
namespace {

struct PointObject {
  std::string class_name;
  Eigen::Vector3d position_m;
};

/// Reads a CSV with a header; returns rows as column-name -> text. Throws InputError.
std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (line.back() == ',') cells.emplace_back();  // an empty last field (getline drops it)
    if (header.empty()) {
      header = cells;
      continue;
    }
    if (cells.size() != header.size()) {
      throw InputError(path + ":" + std::to_string(line_no) + ": expected " + std::to_string(header.size()) +
                       " columns, found " + std::to_string(cells.size()));
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& key, const std::string& path) {
  auto it = row.find(key);
  if (it == row.end()) throw InputError(path + ": column '" + key + "' is missing");
  try {
    const double v = std::stod(it->second);
    if (!std::isfinite(v)) throw std::invalid_argument("not finite");
    return v;
  } catch (const std::exception&) {
    throw InputError(path + ": column '" + key + "' has a bad value '" + it->second + "'");
  }
}

/// Objects in the global frame; rows of objects only in a robot's own frame (column "frame" other
/// than "global": the robot was never placed) are counted in *unplaced, not scored.
std::vector<PointObject> read_objects(const std::string& path, int* unplaced = nullptr) {
  std::vector<PointObject> out;
  for (const auto& row : read_csv(path)) {
    const auto frame = row.find("frame");
    if (frame != row.end() && frame->second != "global") {
      if (unplaced) ++*unplaced;
      continue;
    }
    auto cls = row.find("class");
    if (cls == row.end()) throw InputError(path + ": column 'class' is missing");
    out.push_back({cls->second, {number(row, "x_m", path), number(row, "y_m", path), number(row, "z_m", path)}});
  }
  return out;
}

/// Greedy optimal-enough assignment: closest same-class pairs first, each used once.
ObjectScore score_class(const std::string& cls, const std::vector<PointObject>& truth,
                        const std::vector<PointObject>& found, double max_dist_m) {
  ObjectScore s;
  s.class_name = cls;
  std::vector<const PointObject*> t, f;
  for (const auto& o : truth)
    if (cls == "all" || o.class_name == cls) t.push_back(&o);
  for (const auto& o : found)
    if (cls == "all" || o.class_name == cls) f.push_back(&o);
  s.ground_truth = int(t.size());
  s.detected = int(f.size());
  struct Pair {
    double d;
    size_t i, j;
  };
  std::vector<Pair> pairs;
  for (size_t i = 0; i < t.size(); ++i) {
    for (size_t j = 0; j < f.size(); ++j) {
      if (t[i]->class_name != f[j]->class_name) continue;
      const double d = (t[i]->position_m - f[j]->position_m).head<2>().norm();
      if (d <= max_dist_m) pairs.push_back({d, i, j});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
  std::vector<bool> used_t(t.size()), used_f(f.size());
  for (const auto& p : pairs) {
    if (used_t[p.i] || used_f[p.j]) continue;
    used_t[p.i] = used_f[p.j] = true;
    ++s.matched;
    s.mean_error_xy_m += p.d;
    s.max_error_xy_m = std::max(s.max_error_xy_m, p.d);
    s.mean_error_xyz_m += (t[p.i]->position_m - f[p.j]->position_m).norm();
  }
  if (s.matched) {
    s.mean_error_xy_m /= s.matched;
    s.mean_error_xyz_m /= s.matched;
  }
  return s;
}

/// Scores every report on its own against the nearest same-class truth (see RobotFrameScore).
ObjectScore score_reports(const std::string& cls, const std::vector<PointObject>& truth,
                          const std::vector<PointObject>& reports, double max_dist_m) {
  ObjectScore s;
  s.class_name = cls;
  std::vector<bool> found(truth.size(), false);
  for (size_t i = 0; i < truth.size(); ++i) s.ground_truth += cls == "all" || truth[i].class_name == cls;
  for (const PointObject& r : reports) {
    if (cls != "all" && r.class_name != cls) continue;
    ++s.detected;
    int best = -1;
    double best_d = max_dist_m;
    for (size_t i = 0; i < truth.size(); ++i) {
      const double d = (truth[i].position_m - r.position_m).head<2>().norm();
      if (truth[i].class_name == r.class_name && d <= best_d) best_d = d, best = int(i);
    }
    if (best < 0) continue;
    found[size_t(best)] = true;
    ++s.matched;
    s.mean_error_xy_m += best_d;
    s.max_error_xy_m = std::max(s.max_error_xy_m, best_d);
    s.mean_error_xyz_m += (truth[size_t(best)].position_m - r.position_m).norm();
  }
  if (s.matched) s.mean_error_xy_m /= s.matched, s.mean_error_xyz_m /= s.matched;
  // recall() = matched / ground_truth: count found objects, not matched reports, for it.
  int objects_found = 0;
  for (size_t i = 0; i < truth.size(); ++i) objects_found += found[i] && (cls == "all" || truth[i].class_name == cls);
  s.objects_found = objects_found;
  return s;
}

/// Places objects_robot_frame.csv through each robot's true start and through the true pose of
/// each report's anchor keyframe.
std::vector<RobotFrameScore> score_robot_frame(const std::string& gt_dir, const std::string& results_dir,
                                               const std::vector<PointObject>& truth,
                                               const std::vector<std::string>& classes, double max_dist_m) {
  namespace fs = std::filesystem;
  const fs::path file = fs::path(results_dir) / "objects_robot_frame.csv";
  const fs::path starts_file = fs::path(gt_dir) / "gt_robots.csv";
  if (!fs::exists(file) || !fs::exists(starts_file)) return {};
  std::map<int, SE2> starts;
  for (const auto& row : read_csv(starts_file.string()))
    starts[int(number(row, "id", starts_file.string()))] =
        SE2(number(row, "start_x", starts_file.string()), number(row, "start_y", starts_file.string()),
            number(row, "start_yaw", starts_file.string()));
  std::map<int, Trajectory> gt;
  std::vector<PointObject> by_start, by_anchor;
  const std::string path = file.string();
  for (const auto& row : read_csv(path)) {
    auto cls = row.find("class");
    if (cls == row.end()) throw InputError(path + ": column 'class' is missing");
    const int robot = int(number(row, "robot", path));
    const auto start = starts.find(robot);
    if (start == starts.end())
      throw InputError(path + ": robot " + std::to_string(robot) + " is not in " + starts_file.string());
    const Eigen::Vector3d p_local(number(row, "x_m", path), number(row, "y_m", path), number(row, "z_m", path));
    by_start.push_back({cls->second, start->second.to_isometry3() * p_local});
    if (!gt.count(robot)) {
      const fs::path g = fs::path(gt_dir) / ("gt_robot" + std::to_string(robot) + ".csv");
      gt[robot] = fs::exists(g) ? read_trajectory_csv(g.string()) : Trajectory{};
    }
    const SE2 T_local_anchor(number(row, "anchor_x_m", path), number(row, "anchor_y_m", path),
                             number(row, "anchor_yaw_rad", path));
    const auto truth_anchor = interpolate_pose(gt[robot], StampNs(number(row, "anchor_stamp_ns", path)));
    if (truth_anchor)
      by_anchor.push_back({cls->second, (*truth_anchor * T_local_anchor.inverse()).to_isometry3() * p_local});
  }
  std::vector<RobotFrameScore> out{{"true start", {}, {}}, {"true anchor", {}, {}}};
  for (RobotFrameScore& r : out) {
    const std::vector<PointObject>& reports = r.placement == "true start" ? by_start : by_anchor;
    for (const auto& c : classes) r.classes.push_back(score_reports(c, truth, reports, max_dist_m));
    r.objects = score_reports("all", truth, reports, max_dist_m);
  }
  return out;
}

std::optional<MapConsistency> map_consistency(const std::vector<std::pair<Trajectory, Trajectory>>& estimate_truth) {
  std::vector<Eigen::Vector2d> est, ref;
  MapConsistency c;
  for (const auto& [estimate, truth] : estimate_truth) {
    const size_t before = est.size();
    for (const StampedPose& p : estimate) {
      if (const auto r = interpolate_pose(truth, p.stamp_ns)) {
        est.push_back(p.pose.translation());
        ref.push_back(r->translation());
      }
    }
    if (est.size() > before) ++c.robots;
  }
  if (est.size() < 2) return std::nullopt;
  const SE2 T = align_points_2d(est, ref);
  double sq = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    const double e = (T * est[i] - ref[i]).norm();
    sq += e * e;
    c.ate_max_m = std::max(c.ate_max_m, e);
  }
  c.keyframes = int(est.size());
  c.ate_rmse_m = std::sqrt(sq / double(est.size()));
  c.rotation_deg = T.yaw() * 180.0 / M_PI;
  c.shift_m = T.translation().norm();
  c.T_world_map = T;
  return c;
}

}  // namespace

MissionScore evaluate_mission(const std::string& gt_dir, const std::string& results_dir, const EvalOptions& options) {
  namespace fs = std::filesystem;
  MissionScore score;
  std::vector<std::pair<Trajectory, Trajectory>> estimate_truth;
  for (int id = 0; id < 1000; ++id) {
    const fs::path gt = fs::path(gt_dir) / ("gt_robot" + std::to_string(id) + ".csv");
    if (!fs::exists(gt)) continue;
    RobotScore rs;
    rs.robot = RobotId(id);
    const fs::path est = fs::path(results_dir) / ("trajectory_robot" + std::to_string(id) + ".csv");
    if (fs::exists(est)) {
      const Trajectory reference = read_trajectory_csv(gt.string());
      const Trajectory estimate = read_trajectory_csv(est.string());
      rs.keyframes = int(estimate.size());
      TrajectoryErrorOptions global;
      global.align = false;
      rs.global = trajectory_error(estimate, reference, global);
      rs.aligned = trajectory_error(estimate, reference);
      estimate_truth.emplace_back(estimate, reference);
    }
    score.robots.push_back(rs);
  }
  score.map_consistency = map_consistency(estimate_truth);
  const auto truth = read_objects((fs::path(gt_dir) / "gt_objects.csv").string());
  const auto found = read_objects((fs::path(results_dir) / "objects.csv").string(), &score.unplaced_objects);
  std::vector<std::string> classes;
  for (const auto& o : truth) {
    if (std::find(classes.begin(), classes.end(), o.class_name) == classes.end()) classes.push_back(o.class_name);
  }
  for (const auto& o : found) {
    if (std::find(classes.begin(), classes.end(), o.class_name) == classes.end()) classes.push_back(o.class_name);
  }
  std::sort(classes.begin(), classes.end());
  for (const auto& c : classes) score.classes.push_back(score_class(c, truth, found, options.object_match_distance_m));
  score.objects = score_class("all", truth, found, options.object_match_distance_m);
  score.robot_frame = score_robot_frame(gt_dir, results_dir, truth, classes, options.object_match_distance_m);
  score.coverage =
      evaluate_coverage(gt_dir, results_dir, score.map_consistency ? score.map_consistency->T_world_map : SE2());
  return score;
}

nlohmann::json to_json(const MissionScore& score) {
  nlohmann::json j;
  j["robots"] = nlohmann::json::array();
  for (const auto& r : score.robots) {
    nlohmann::json rj{{"id", r.robot.value}, {"keyframes", r.keyframes}};
    if (r.global) rj["ate_global_rmse_m"] = r.global->ate_rmse_m, rj["ate_global_max_m"] = r.global->ate_max_m;
    if (r.aligned)
      rj["ate_aligned_rmse_m"] = r.aligned->ate_rmse_m, rj["rpe_trans_mean_m"] = r.aligned->rpe_trans_mean_m;
    j["robots"].push_back(rj);
  }
  if (const auto& c = score.map_consistency) {
    j["map_consistency"] = {
        {"robots", c->robots},       {"keyframes", c->keyframes},       {"ate_rmse_m", c->ate_rmse_m},
        {"ate_max_m", c->ate_max_m}, {"rotation_deg", c->rotation_deg}, {"shift_m", c->shift_m}};
  }
  auto obj = [](const ObjectScore& s) {
    return nlohmann::json{{"class", s.class_name},
                          {"ground_truth", s.ground_truth},
                          {"detected", s.detected},
                          {"matched", s.matched},
                          {"recall", s.recall()},
                          {"precision", s.precision()},
                          {"mean_error_xy_m", s.mean_error_xy_m},
                          {"max_error_xy_m", s.max_error_xy_m},
                          {"mean_error_xyz_m", s.mean_error_xyz_m}};
  };
  j["objects"] = obj(score.objects);
  j["unplaced_objects"] = score.unplaced_objects;
  j["classes"] = nlohmann::json::array();
  for (const auto& c : score.classes) j["classes"].push_back(obj(c));
  j["robot_frame"] = nlohmann::json::array();
  for (const auto& r : score.robot_frame) {
    nlohmann::json rj{{"placement", r.placement}, {"objects", obj(r.objects)}, {"classes", nlohmann::json::array()}};
    // Every report on its own: recall counts objects found by any report (see RobotFrameScore).
    auto fix = [](nlohmann::json& o, const ObjectScore& c) {
      o["objects_found"] = c.objects_found;
      o["recall"] = c.ground_truth ? double(c.objects_found) / c.ground_truth : 0.0;
    };
    fix(rj["objects"], r.objects);
    for (const auto& c : r.classes) {
      rj["classes"].push_back(obj(c));
      fix(rj["classes"].back(), c);
    }
    j["robot_frame"].push_back(rj);
  }
  if (score.coverage) {
    j["coverage"] = {{"reachable_m2", score.coverage->reachable_m2},
                     {"covered_m2", score.coverage->covered_m2},
                     {"fraction", score.coverage->fraction()}};
  }
  return j;
}

std::string format_score(const MissionScore& score) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  for (const auto& r : score.robots) {
    s << "  robot " << r.robot.value << ": " << r.keyframes << " keyframes";
    if (r.global)
      s << ", trajectory error " << r.global->ate_rmse_m << " m RMSE (max " << r.global->ate_max_m << " m)";
    else
      s << ", no trajectory";
    s << "\n";
  }
  if (const auto& c = score.map_consistency) {
    s << "  the merged map in itself (" << c->robots << " robots aligned to the truth as one): " << c->ate_rmse_m
      << " m RMSE (max " << c->ate_max_m << " m); it sits " << c->rotation_deg << " deg and " << c->shift_m
      << " m off the world\n";
  }
  auto line = [&](const ObjectScore& o) {
    s << "  " << o.class_name << ": found " << o.matched << "/" << o.ground_truth << " (recall " << o.recall()
      << ", precision " << o.precision() << "), position error " << o.mean_error_xy_m << " m mean xy, "
      << o.max_error_xy_m << " m max\n";
  };
  for (const auto& c : score.classes) line(c);
  line(score.objects);
  if (const auto& c = score.coverage) {
    s.precision(1);
    s << "  explored: " << c->covered_m2 << " of " << c->reachable_m2 << " m2 reachable (" << 100.0 * c->fraction()
      << " %)\n";
    s.precision(3);
  }
  if (score.unplaced_objects > 0) {
    s << "  + " << score.unplaced_objects
      << " object(s) only in the own frame of a robot never placed on the map (not scored above)\n";
  }
  for (const auto& r : score.robot_frame) {
    s << "  objects in each robot's own frame, placed by its " << r.placement << " (every report on its own):\n";
    auto rline = [&](const ObjectScore& o) {
      s << "    " << o.class_name << ": " << o.objects_found << "/" << o.ground_truth << " objects found by "
        << o.detected << " reports (precision " << o.precision() << "), position error " << o.mean_error_xy_m
        << " m mean xy, " << o.max_error_xy_m << " m max\n";
    };
    for (const auto& c : r.classes) rline(c);
    rline(r.objects);
  }
  return s.str();
}

}  // namespace cairn::eval
