// export_all and the text formats (GeoJSON, CSV, g2o). Images: exporter_image.cpp; clouds and
// OctoMap: exporter_clouds.cpp.
#include "base_station/export/exporter.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

namespace cairn::base {
namespace {

std::string join_robots(const std::vector<RobotId>& robots, const char* sep) {
  std::string s;
  for (size_t i = 0; i < robots.size(); ++i) s += (i ? sep : "") + std::to_string(robots[i].value);
  return s;
}

bool write_text(const std::string& path, const std::string& text, std::string* error) {
  std::ofstream out(path, std::ios::binary);
  if (!out) {
    *error = "cannot open for writing";
    return false;
  }
  out << text;
  out.flush();
  if (!out) {
    *error = "write failed";
    return false;
  }
  return true;
}

/// Runs one writer and records its outcome; exceptions from libraries become failures.
template <typename Fn>
void run(ExportSummary* summary, const std::string& path, Fn&& fn) {
  ExportedFile f{path, false, {}};
  try {
    f.ok = fn(path, &f.error);
  } catch (const std::exception& e) {
    f.ok = false;
    f.error = std::string("exception: ") + e.what();
  } catch (...) {
    f.ok = false;
    f.error = "unknown exception";
  }
  if (!f.ok && f.error.empty()) f.error = "write failed";
  summary->files.push_back(std::move(f));
}

}  // namespace

namespace {

std::string join_ids(const std::vector<ObjectId>& ids) {
  std::string s;
  for (size_t i = 0; i < ids.size(); ++i) s += (i ? ";" : "") + object_key(ids[i]);
  return s;
}

/// Where an object is in its (first) robot's own frame: for an unplaced object its own position,
/// for a placed one its global position taken back to that robot's local frame.
Eigen::Vector2d local_position(const MapperData& data, const GlobalObject& o) {
  const Eigen::Vector2d p = o.position_m.head<2>();
  if (o.frame.valid() || o.robots.empty() || !data.linked(o.robots.front())) return p;
  return data.correction(o.robots.front()).inverse() * p;
}

}  // namespace

bool write_objects_geojson(const MergedMap& merged, const std::string& path, std::string* error) {
  nlohmann::json features = nlohmann::json::array();
  for (const GlobalObject* object : merged.all_objects()) {
    const GlobalObject& o = *object;
    std::vector<int> robots;
    for (RobotId r : o.robots) robots.push_back(r.value);
    std::vector<std::string> aliases;
    for (ObjectId a : o.aliases) aliases.push_back(object_key(a));
    nlohmann::json properties = {{"id", object_key(o.id)},
                                 {"class", o.class_name},
                                 {"confidence", o.confidence},
                                 {"frame", frame_name(o.frame)},
                                 {"aliases", aliases},
                                 {"z_m", o.position_m.z()},
                                 {"robots", robots},
                                 {"observations", o.observations},
                                 {"size", {o.size_m.x(), o.size_m.y(), o.size_m.z()}},
                                 {"verdict", to_string(o.verdict)},
                                 {"verdict_note", o.verdict_note}};
    nlohmann::json geometry = nullptr;  // GeoJSON: an unlocated feature (its robot is not placed)
    if (o.frame.valid()) {
      const FromEntry w = from_entry(*merged.data, o.frame, o.position_m.head<2>());
      properties["robot_frame_m"] = {o.position_m.x(), o.position_m.y()};
      properties["where"] = describe(o.frame, w);
    } else {
      geometry = {{"type", "Point"}, {"coordinates", {o.position_m.x(), o.position_m.y()}}};
      if (!o.robots.empty()) {
        const Eigen::Vector2d local = local_position(*merged.data, o);
        properties["robot_frame_m"] = {local.x(), local.y()};
      }
    }
    features.push_back({{"type", "Feature"}, {"geometry", geometry}, {"properties", properties}});
  }
  const nlohmann::json doc = {
      {"type", "FeatureCollection"},
      {"properties",
       {{"crs",
         "cairn global map frame, metres; features without geometry are in their robot's own frame "
         "(properties.frame, robot_frame_m), the robot not being placed yet"}}},
      {"features", features}};
  return write_text(path, doc.dump(2) + "\n", error);
}

namespace {

/// Free text in one CSV field without quoting: commas become semicolons, line breaks spaces.
std::string csv_safe(std::string text) {
  for (char& c : text) {
    if (c == ',') c = ';';
    if (c == '\n' || c == '\r' || c == '"') c = ' ';
  }
  return text;
}

}  // namespace

bool write_objects_csv(const MergedMap& merged, const std::string& path, std::string* error) {
  std::ostringstream s;
  s << std::setprecision(9);
  // x_m, y_m, z_m are in `frame`: "global", or "robotN" (robot N's own frame, it is not placed yet).
  // local_*: in the frame of the object's first robot (its own for an unplaced object).
  // verdict: the operator's (unreviewed, confirmed, false); verdict_note with commas as semicolons.
  s << "id,class,confidence,x_m,y_m,z_m,robots,observations,size_x_m,size_y_m,size_z_m,frame,aliases,"
       "local_robot,local_x_m,local_y_m,verdict,verdict_note\n";
  for (const GlobalObject* object : merged.all_objects()) {
    const GlobalObject& o = *object;
    const Eigen::Vector2d local = local_position(*merged.data, o);
    s << object_key(o.id) << ',' << o.class_name << ',' << o.confidence << ',' << o.position_m.x() << ','
      << o.position_m.y() << ',' << o.position_m.z() << ',' << join_robots(o.robots, ";") << ',' << o.observations
      << ',' << o.size_m.x() << ',' << o.size_m.y() << ',' << o.size_m.z() << ',' << frame_name(o.frame) << ','
      << join_ids(o.aliases) << ',' << (o.robots.empty() ? -1 : o.robots.front().value) << ',' << local.x() << ','
      << local.y() << ',' << to_string(o.verdict) << ',' << csv_safe(o.verdict_note) << '\n';
  }
  return write_text(path, s.str(), error);
}

namespace {

/// A range-bearing observation as a Cartesian point in the observing pose's frame, and the
/// information of that point: (J diag(sigma_range^2, sigma_bearing^2) J^T)^-1, J = d(point)/d(range, bearing).
std::pair<Eigen::Vector2d, Eigen::Matrix2d> cartesian_observation(const LandmarkEdge& e) {
  const double c = std::cos(e.bearing_rad), s = std::sin(e.bearing_rad), r = e.range_m;
  Eigen::Matrix2d J;
  J << c, -r * s, s, r * c;
  const Eigen::Vector2d var(e.sigma_range_m * e.sigma_range_m, e.sigma_bearing_rad * e.sigma_bearing_rad);
  const Eigen::Matrix2d covariance = J * var.asDiagonal() * J.transpose();
  return {Eigen::Vector2d(r * c, r * s), covariance.inverse()};
}

}  // namespace

bool write_graph_g2o(const KeyframePoseGraph& graph, const std::string& path, std::string* error) {
  std::ostringstream s;
  s << std::setprecision(12);
  s << "# cairn pose graph. Vertex id = dense index over keyframes in (robot, seq) order, then over the"
       " point nodes (markers, merged objects, then sightings); '# KEYFRAME <vertex> <robot> <seq>',"
       " '# MARKER <vertex> <marker id>', '# OBJECT <vertex> <robot> <seq>' and"
       " '# SIGHTING <vertex> <sighting index>' lines give the mapping.\n";
  std::map<KeyframeId, int> index;
  for (const auto& [id, pose] : graph.estimates()) {
    const int v = int(index.size());
    index[id] = v;
    s << "# KEYFRAME " << v << ' ' << id.robot.value << ' ' << id.seq << '\n';
    s << "VERTEX_SE2 " << v << ' ' << pose.x() << ' ' << pose.y() << ' ' << pose.yaw() << '\n';
  }
  auto upper = [&](const Eigen::Matrix3d& I) {
    s << ' ' << I(0, 0) << ' ' << I(0, 1) << ' ' << I(0, 2) << ' ' << I(1, 1) << ' ' << I(1, 2) << ' ' << I(2, 2);
  };
  for (const PoseGraphEdge& e : graph.edges()) {
    s << "EDGE_SE2 " << index.at(e.from) << ' ' << index.at(e.to) << ' ' << e.T_from_to.x() << ' ' << e.T_from_to.y()
      << ' ' << e.T_from_to.yaw();
    upper(e.information);
    s << '\n';
  }
  for (const auto& [id, p] : graph.priors()) {
    s << "EDGE_PRIOR_SE2 " << index.at(id) << ' ' << p.T_world_node.x() << ' ' << p.T_world_node.y() << ' '
      << p.T_world_node.yaw();
    upper(p.information);
    s << '\n';
  }
  // Point nodes (VERTEX_XY) and their observations as g2o's EDGE_SE2_XY (the point in the pose's frame).
  std::map<PointNodeId, int> points;
  for (const auto& [id, p] : graph.point_estimates()) {
    const int v = int(index.size() + points.size());
    points[id] = v;
    if (const auto* marker = std::get_if<LandmarkId>(&id)) {
      s << "# MARKER " << v << ' ' << marker->value << '\n';
    } else if (const auto* sighting = std::get_if<SightingNodeId>(&id)) {
      s << "# SIGHTING " << v << ' ' << sighting->index << '\n';
    } else {
      const ObjectId& object = std::get<ObjectId>(id);
      s << "# OBJECT " << v << ' ' << object.robot.value << ' ' << object.seq << '\n';
    }
    s << "VERTEX_XY " << v << ' ' << p.x() << ' ' << p.y() << '\n';
  }
  for (const LandmarkEdge& e : graph.landmark_edges()) {
    const auto [p, I] = cartesian_observation(e);
    s << "EDGE_SE2_XY " << index.at(e.from) << ' ' << points.at(e.landmark) << ' ' << p.x() << ' ' << p.y() << ' '
      << I(0, 0) << ' ' << I(0, 1) << ' ' << I(1, 1) << '\n';
  }
  return write_text(path, s.str(), error);
}

ExportSummary export_all(const MergedMap& merged, const std::string& out_dir, const ExportOptions& options,
                         const ExplorationPlan* plan) {
  ExportSummary summary;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec || !std::filesystem::is_directory(out_dir, ec)) {
    summary.files.push_back({out_dir, false, "cannot create directory: " + (ec ? ec.message() : "not a directory")});
    return summary;
  }
  const std::string dir = out_dir + "/";
  const std::vector<GlobalObject>& objects = merged.objects;
  run(&summary, dir + "map.pgm",
      [&](const std::string&, std::string*) { return merged.grid->write_pgm_yaml(dir + "map"); });
  summary.files.push_back({dir + "map.yaml", summary.files.back().ok, summary.files.back().error});
  run(&summary, dir + "map.png",
      [&](const std::string& p, std::string* e) { return write_map_png(merged, p, options, e, plan); });
  run(&summary, dir + "objects.geojson",
      [&](const std::string& p, std::string* e) { return write_objects_geojson(merged, p, e); });
  run(&summary, dir + "objects.csv",
      [&](const std::string& p, std::string* e) { return write_objects_csv(merged, p, e); });
  if (merged.robot_frame_maps)
    for (const RobotFrameMap& m : *merged.robot_frame_maps) {
      run(&summary, dir + "robot" + std::to_string(m.robot.value) + "_own_frame.png",
          [&](const std::string& p, std::string* e) { return write_robot_frame_png(m, p, options, e); });
    }
  for (const RobotSummary& r : merged.robots) {  // placed since an earlier export: its own map is not the story now
    if (r.linked) std::filesystem::remove(dir + "robot" + std::to_string(r.id.value) + "_own_frame.png", ec);
  }
  run(&summary, dir + "objects_robot_frame.csv", [&](const std::string& p, std::string* e) {
    return write_text(p, robot_frame_objects_csv(merged.data->keyframes, merged.data->reports), e);
  });
  for (const GlobalObject& o : objects) {
    run(&summary, dir + "object_" + object_key(o.id) + ".ply",
        [&](const std::string& p, std::string* e) { return write_object_ply(o, p, e); });
  }
  run(&summary, dir + "objects.bt", [&](const std::string& p, std::string* e) {
    return write_objects_octomap(objects, options.octomap_resolution_m, p, e);
  });
  run(&summary, dir + "graph.g2o",
      [&](const std::string& p, std::string* e) { return write_graph_g2o(*merged.graph, p, e); });
  for (const auto& [robot, robot_trajectory] : merged.trajectories) {
    const auto& trajectory = robot_trajectory;  // a lambda may not capture a structured binding (C++17)
    run(&summary, dir + "trajectory_robot" + std::to_string(robot.value) + ".csv",
        [&](const std::string& p, std::string*) { return write_trajectory_csv(p, trajectory); });
  }
  return summary;
}

}  // namespace cairn::base
