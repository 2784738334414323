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
    if (header.empty()) { header = cells; continue; }
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

std::vector<PointObject> read_objects(const std::string& path) {
  std::vector<PointObject> out;
  for (const auto& row : read_csv(path)) {
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
  for (const auto& o : truth) if (cls == "all" || o.class_name == cls) t.push_back(&o);
  for (const auto& o : found) if (cls == "all" || o.class_name == cls) f.push_back(&o);
  s.ground_truth = int(t.size());
  s.detected = int(f.size());
  struct Pair { double d; size_t i, j; };
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

}  // namespace

MissionScore evaluate_mission(const std::string& gt_dir, const std::string& results_dir, const EvalOptions& options) {
  namespace fs = std::filesystem;
  MissionScore score;
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
    }
    score.robots.push_back(rs);
  }
  const auto truth = read_objects((fs::path(gt_dir) / "gt_objects.csv").string());
  const auto found = read_objects((fs::path(results_dir) / "objects.csv").string());
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
  return score;
}

nlohmann::json to_json(const MissionScore& score) {
  nlohmann::json j;
  j["robots"] = nlohmann::json::array();
  for (const auto& r : score.robots) {
    nlohmann::json rj{{"id", r.robot.value}, {"keyframes", r.keyframes}};
    if (r.global) rj["ate_global_rmse_m"] = r.global->ate_rmse_m, rj["ate_global_max_m"] = r.global->ate_max_m;
    if (r.aligned) rj["ate_aligned_rmse_m"] = r.aligned->ate_rmse_m, rj["rpe_trans_mean_m"] = r.aligned->rpe_trans_mean_m;
    j["robots"].push_back(rj);
  }
  auto obj = [](const ObjectScore& s) {
    return nlohmann::json{{"class", s.class_name}, {"ground_truth", s.ground_truth}, {"detected", s.detected},
                          {"matched", s.matched}, {"recall", s.recall()}, {"precision", s.precision()},
                          {"mean_error_xy_m", s.mean_error_xy_m}, {"max_error_xy_m", s.max_error_xy_m},
                          {"mean_error_xyz_m", s.mean_error_xyz_m}};
  };
  j["objects"] = obj(score.objects);
  j["classes"] = nlohmann::json::array();
  for (const auto& c : score.classes) j["classes"].push_back(obj(c));
  return j;
}

std::string format_score(const MissionScore& score) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  for (const auto& r : score.robots) {
    s << "  robot " << r.robot.value << ": " << r.keyframes << " keyframes";
    if (r.global) s << ", trajectory error " << r.global->ate_rmse_m << " m RMSE (max " << r.global->ate_max_m << " m)";
    else s << ", no trajectory";
    s << "\n";
  }
  auto line = [&](const ObjectScore& o) {
    s << "  " << o.class_name << ": found " << o.matched << "/" << o.ground_truth << " (recall " << o.recall()
      << ", precision " << o.precision() << "), position error " << o.mean_error_xy_m << " m mean xy, "
      << o.max_error_xy_m << " m max\n";
  };
  for (const auto& c : score.classes) line(c);
  line(score.objects);
  return s.str();
}

}  // namespace cairn::eval
