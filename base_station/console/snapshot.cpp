#include "base_station/console/snapshot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <optional>

#include "base_station/core/saliency_layer.h"
#include "base_station/export/exporter.h"

namespace cairn::base {
namespace {

/// Keeps at most max_points, evenly spaced, always including the last one.
template <typename T>
std::vector<size_t> decimate(const std::vector<T>& v, size_t max_points) {
  std::vector<size_t> idx;
  if (v.empty() || max_points == 0) return idx;
  const size_t step = (v.size() + max_points - 1) / max_points;
  for (size_t i = 0; i < v.size(); i += step) idx.push_back(i);
  if (idx.back() != v.size() - 1) {
    if (idx.size() >= max_points)
      idx.back() = v.size() - 1;
    else
      idx.push_back(v.size() - 1);
  }
  return idx;
}

std::string robots_text(const std::vector<RobotId>& robots) {
  std::string s;
  for (size_t i = 0; i < robots.size(); ++i) {
    s += (i == 0 ? "" : i + 1 == robots.size() ? " and " : ", ") + std::to_string(robots[i].value);
  }
  return (robots.size() > 1 ? "robots " : "robot ") + s;
}

nlohmann::json pose_json(const SE2& T) { return {{"x_m", T.x()}, {"y_m", T.y()}, {"yaw_deg", T.yaw() * 180.0 / M_PI}}; }

/// The operator's latest alignment of the robot's map and what the base made of it (null: none).
nlohmann::json alignment_json(const MergedMap& merged, RobotId robot) {
  const auto it = merged.alignments.find(robot);
  if (it == merged.alignments.end()) return nullptr;
  const AlignmentVerdict& v = it->second;
  return {{"state", to_string(v.state)},
          {"reason", v.reason},
          {"requested", pose_json(v.requested)},
          {"placed", v.state == AlignmentState::kAccepted ? pose_json(v.placed) : nlohmann::json()},
          {"closures", v.closures}};
}

/// An unlinked robot's own map as points the console can move over the global map while the
/// operator aligns it: its walls (occupied cells, at most max_points, evenly kept) and its path,
/// both in its own frame.
nlohmann::json own_frame_outline(const RobotFrameMap& m, size_t max_points) {
  std::vector<Eigen::Vector2d> walls;
  for (int row = 0; row < m.grid.height(); ++row) {
    for (int col = 0; col < m.grid.width(); ++col) {
      if (m.grid.probability(col, row) >= 0.65) walls.push_back(m.grid.cell_center_m(col, row));
    }
  }
  nlohmann::json walls_m = nlohmann::json::array(), path_m = nlohmann::json::array();
  for (size_t i : decimate(walls, max_points)) walls_m.push_back({walls[i].x(), walls[i].y()});
  for (size_t i : decimate(m.trajectory, max_points / 10))
    path_m.push_back({m.trajectory[i].pose.x(), m.trajectory[i].pose.y()});
  return {{"walls_m", walls_m}, {"path_m", path_m}};
}

/// A placed robot's newest reported pose on the map (from its link's "pose_local").
std::optional<SE2> pose_on_map(const RobotSummary& r, const nlohmann::json& link) {
  if (!r.linked || !link.contains("pose_local") || link["pose_local"].size() != 3) return std::nullopt;
  return r.T_global_local * SE2(link["pose_local"][0].get<double>(), link["pose_local"][1].get<double>(),
                                link["pose_local"][2].get<double>());
}

nlohmann::json robot_json(const MergedMap& merged, const RobotSummary& r, const nlohmann::json& link_stats,
                          const SnapshotOptions& options) {
  nlohmann::json trajectory = nlohmann::json::array();
  const Trajectory& t = merged.trajectory(r.id);
  for (size_t i : decimate(t, options.max_trajectory_points)) {
    trajectory.push_back({t[i].pose.x(), t[i].pose.y()});
  }
  const std::string key = std::to_string(r.id.value);
  const nlohmann::json link =
      link_stats.is_object() && link_stats.contains(key) ? link_stats[key] : nlohmann::json::object();
  nlohmann::json pose_m;  // its newest reported pose on the map (placed robots only): [x, y, yaw]
  if (const std::optional<SE2> p = pose_on_map(r, link)) pose_m = {p->x(), p->y(), p->yaw()};
  nlohmann::json path_m = nlohmann::json::array();  // the path it is driving, on the map (placed robots)
  if (r.linked && link.contains("path_local") && link["path_local"].is_array()) {
    for (const auto& p : link["path_local"]) {
      const Eigen::Vector2d g = r.T_global_local * Eigen::Vector2d(p[0].get<double>(), p[1].get<double>());
      path_m.push_back({g.x(), g.y()});
    }
  }
  return {{"id", r.id.value},
          {"linked", r.linked},
          {"keyframes", r.keyframes},
          {"missing_keyframes", r.missing_keyframes},
          {"objects", r.objects},
          {"first_stamp_s", ns_to_sec(r.first_stamp_ns)},
          {"last_stamp_s", ns_to_sec(r.last_stamp_ns)},
          {"time_to_link_s", r.time_to_link_s >= 0 ? nlohmann::json(r.time_to_link_s) : nlohmann::json()},
          {"alignment", alignment_json(merged, r.id)},
          {"own_map", r.linked || r.keyframes == 0
                          ? nlohmann::json()
                          : nlohmann::json("/api/robots/" + std::to_string(r.id.value) + "/own_map.png")},
          {"correction",
           {{"x_m", r.T_global_local.x()}, {"y_m", r.T_global_local.y()}, {"yaw_rad", r.T_global_local.yaw()}}},
          {"trajectory", trajectory},
          {"pose_m", pose_m},
          {"path_m", path_m},
          {"link", link}};
}

}  // namespace

nlohmann::json object_json(const GlobalObject& o, const MergedMap& merged) {
  std::vector<int> robots;
  for (RobotId r : o.robots) robots.push_back(r.value);
  std::vector<std::string> reports;
  for (ObjectId id : o.reports) reports.push_back(object_key(id));
  std::vector<std::string> aliases;
  for (ObjectId id : o.aliases) aliases.push_back(object_key(id));
  const std::string key = object_key(o.id);
  nlohmann::json where;  // unplaced: where it is, told from where its robot entered
  if (o.frame.valid() && merged.data) {
    const FromEntry w = from_entry(*merged.data, o.frame, o.position_m.head<2>());
    where = {{"distance_m", w.distance_m},
             {"bearing_deg", w.bearing_rad * 180.0 / M_PI},
             {"path_m", w.path_m},
             {"text", describe(o.frame, w)}};
  }
  return {
      {"id", key},
      {"frame", frame_name(o.frame)},
      {"aliases", aliases},
      {"from_entry", where},
      {"class", o.class_name},
      {"confidence", o.confidence},
      {"position_m", {o.position_m.x(), o.position_m.y(), o.position_m.z()}},
      {"sigma_m", {std::sqrt(o.covariance(0, 0)), std::sqrt(o.covariance(1, 1)), std::sqrt(o.covariance(2, 2))}},
      {"size_m", {o.size_m.x(), o.size_m.y(), o.size_m.z()}},
      {"robots", robots},
      {"reports", reports},
      {"observations", o.observations},
      {"last_stamp_s", ns_to_sec(o.last_stamp_ns)},
      {"thumbnail", o.thumbnail_jpeg.empty()
                        ? nlohmann::json()
                        : nlohmann::json("/api/objects/" + key + "/thumbnail.jpg?v=" + std::to_string(o.observations))},
      {"cloud", "/api/objects/" + key + "/cloud"},
      {"cloud_points", o.cloud_global.size()},
      {"verdict", to_string(o.verdict)},
      {"verdict_note", o.verdict_note}};
}

namespace {

nlohmann::json alerts_json(const MergedMap& merged, const nlohmann::json& link_stats) {
  const std::vector<RobotSummary>& robots = merged.robots;
  nlohmann::json alerts = nlohmann::json::array();
  for (const GlobalObject* object : merged.all_objects()) {
    const GlobalObject& o = *object;
    const char* level = o.class_name == "victim" ? "critical" : o.class_name == "hazard" ? "warning" : "info";
    char at[64];
    std::snprintf(at, sizeof(at), " at (%.1f, %.1f) m", o.position_m.x(), o.position_m.y());
    std::string where = at;
    if (o.frame.valid() && merged.data) {  // never hidden: told from where its robot entered
      where = ", not on the map yet: " + describe(o.frame, from_entry(*merged.data, o.frame, o.position_m.head<2>()));
    }
    std::string what = o.class_name;
    if (!what.empty()) what[0] = char(std::toupper(static_cast<unsigned char>(what[0])));
    alerts.push_back({{"key", "object:" + object_key(o.id)},
                      {"level", level},
                      {"object", object_key(o.id)},
                      {"stamp_s", ns_to_sec(o.last_stamp_ns)},
                      {"frame", frame_name(o.frame)},
                      {"text", what + " found by " + robots_text(o.robots) + where}});
  }
  for (const RobotSummary& r : robots) {
    if (!r.linked) {
      alerts.push_back(
          {{"key", "unlinked:" + std::to_string(r.id.value)},
           {"level", "warning"},
           {"robot", r.id.value},
           {"stamp_s", ns_to_sec(r.last_stamp_ns)},
           {"text", "Robot " + std::to_string(r.id.value) +
                        " is not linked to the global map: its map and finds are shown in its own frame"}});
    }
  }
  // What the robots' links and statuses say: out of contact (nothing heard for 10 s), collision risk,
  // off the map, stuck.
  for (const RobotSummary& r : robots) {
    const std::string id = std::to_string(r.id.value);
    if (!link_stats.is_object() || !link_stats.contains(id)) continue;
    const nlohmann::json& link = link_stats[id];
    const double age_s = link.value("last_heard_age_s", -1.0);
    if (link.value("state", "") == "lost" && age_s >= 10.0) {
      alerts.push_back({{"key", "contact:" + id},
                        {"level", "critical"},
                        {"robot", r.id.value},
                        {"stamp_s", ns_to_sec(r.last_stamp_ns)},
                        {"text", "Robot " + id + " out of contact for " + std::to_string(int(age_s)) + " s"}});
    }
    if (link.value("laser_lost", false)) {
      alerts.push_back({{"key", "laser:" + id},
                        {"level", "critical"},
                        {"robot", r.id.value},
                        {"stamp_s", ns_to_sec(r.last_stamp_ns)},
                        {"text", "Robot " + id + ": laser lost, placed by odometry alone; going home by its map"}});
    }
    if (link.value("collision_risk", false)) {
      alerts.push_back({{"key", "collision:" + id},
                        {"level", "warning"},
                        {"robot", r.id.value},
                        {"stamp_s", ns_to_sec(r.last_stamp_ns)},
                        {"text", "Robot " + id + ": collision risk ahead (its camera's optical flow)"}});
    }
    // Off the merged map by more than a metre: lost in unmapped space, or its placement went wrong.
    const OccupancyGrid& grid = *merged.grid;
    const Eigen::Vector2d lo = grid.origin_m() - Eigen::Vector2d(1, 1);
    const Eigen::Vector2d hi =
        grid.origin_m() + Eigen::Vector2d(grid.width(), grid.height()) * grid.resolution_m() + Eigen::Vector2d(1, 1);
    const std::optional<SE2> pose = pose_on_map(r, link);
    if (pose && grid.width() > 0 &&
        ((pose->translation().array() < lo.array()).any() || (pose->translation().array() > hi.array()).any())) {
      alerts.push_back({{"key", "left:" + id},
                        {"level", "warning"},
                        {"robot", r.id.value},
                        {"stamp_s", ns_to_sec(r.last_stamp_ns)},
                        {"text", "Robot " + id + " has left the map"}});
    }
    if (link.value("nav_state", "") == "stuck") {
      alerts.push_back({{"key", "stuck:" + id},
                        {"level", "warning"},
                        {"robot", r.id.value},
                        {"stamp_s", ns_to_sec(r.last_stamp_ns)},
                        {"text", "Robot " + id + " is stuck"}});
    }
  }
  // Most urgent first, then newest.
  std::stable_sort(alerts.begin(), alerts.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    auto rank = [](const std::string& l) { return l == "critical" ? 0 : l == "warning" ? 1 : 2; };
    const int ra = rank(a["level"]), rb = rank(b["level"]);
    return ra != rb ? ra < rb : a["stamp_s"].get<double>() > b["stamp_s"].get<double>();
  });
  return alerts;
}

}  // namespace

nlohmann::json exploration_json(const ExplorationPlan& plan) {
  nlohmann::json goals = nlohmann::json::array();
  for (const ExplorationGoal& g : plan.goals) {
    goals.push_back({{"robot", g.robot.value},
                     {"x_m", g.goal_m.x()},
                     {"y_m", g.goal_m.y()},
                     {"path_m", g.path_m},
                     {"frontier_m", plan.frontiers[size_t(g.frontier)].length_m},
                     {"saliency", plan.frontiers[size_t(g.frontier)].saliency}});
  }
  std::vector<int> idle;
  for (RobotId r : plan.idle) idle.push_back(r.value);
  nlohmann::json meetings = nlohmann::json::array();
  for (const MeetingGoal& m : plan.meetings) {
    meetings.push_back(
        {{"robot", m.robot.value}, {"teammate", m.teammate.value}, {"x_m", m.goal_m.x()}, {"y_m", m.goal_m.y()}});
  }
  const int salient_cells = plan.saliency ? plan.saliency->cells_above(0.1) : 0;
  return {{"frontiers", plan.frontiers.size()},
          {"goals", goals},
          {"idle", idle},
          {"meetings", meetings},
          {"salient_cells", salient_cells}};
}

nlohmann::json plan_layers_json(const ExplorationPlan& plan) {
  nlohmann::json frontiers = nlohmann::json::array();
  for (const Frontier& f : plan.frontiers)
    frontiers.push_back(
        {{"x_m", f.centre_m.x()}, {"y_m", f.centre_m.y()}, {"length_m", f.length_m}, {"saliency", f.saliency}});
  nlohmann::json saliency = {{"cell_m", 0.0}, {"cells", nlohmann::json::array()}};
  if (plan.saliency) {
    const SaliencyLayer& layer = *plan.saliency;
    saliency["cell_m"] = layer.cell_m();
    for (int r = 0; r < layer.height(); ++r)
      for (int c = 0; c < layer.width(); ++c)
        if (layer.value(c, r) >= 0.1) {
          const Eigen::Vector2d p = layer.centre_m(c, r);
          saliency["cells"].push_back(nlohmann::json::array({p.x(), p.y(), layer.value(c, r)}));
        }
  }
  return {{"frontiers", frontiers}, {"saliency", saliency}, {"unreachable", nlohmann::json::array()}};
}

ConsoleSnapshot make_snapshot(const MergedMap& merged, const nlohmann::json& link_stats, const SnapshotOptions& options,
                              const ExplorationPlan* plan) {
  ConsoleSnapshot s;
  const std::vector<RobotSummary>& robots = merged.robots;
  StampNs mission_ns = 0;
  int linked = 0;
  for (const RobotSummary& r : robots) {
    s.robots.push_back(robot_json(merged, r, link_stats, options));
    mission_ns = std::max(mission_ns, r.last_stamp_ns);
    linked += r.linked;
  }
  const std::vector<const GlobalObject*> objects = merged.all_objects();  // placed, then unplaced
  std::vector<int> unlinked;
  for (const RobotSummary& r : robots) {
    if (!r.linked) unlinked.push_back(r.id.value);
  }
  for (const GlobalObject* object : objects) {
    const GlobalObject& o = *object;
    const std::string key = object_key(o.id);
    s.objects.push_back(object_json(o, merged));
    if (!o.thumbnail_jpeg.empty()) s.thumbnails[key] = o.thumbnail_jpeg;
    nlohmann::json cloud = nlohmann::json::array();
    for (size_t i : decimate(o.cloud_global, options.max_cloud_points)) {
      const ColoredPoint& p = o.cloud_global[i];
      cloud.push_back({p.x, p.y, p.z, p.r, p.g, p.b});
    }
    s.clouds[key] = std::move(cloud);
  }
  s.status = {{"mission_time_s", ns_to_sec(mission_ns)},
              {"mapped_area_m2", merged.grid->known_area_m2()},
              {"robots", robots.size()},
              {"linked_robots", linked},
              {"objects", objects.size()},
              {"unplaced_objects", merged.unplaced_objects.size()},
              {"unlinked_robots", unlinked},
              {"pending_objects", merged.data->pending_objects().size()},
              {"version", merged.version},
              {"alerts", alerts_json(merged, link_stats)}};
  if (plan) s.status["exploration"] = exploration_json(*plan);
  if (plan) s.layers = plan_layers_json(*plan);
  s.grid_cells = GridCells::from(*merged.grid);
  if (options.render_images) s.map_png = render_map_png(merged, {}, plan);
  const MapImageGeometry g = map_image_geometry(*merged.grid);
  s.map_image = {{"valid", g.valid},       {"x0_m", g.x0_m},         {"y_top_m", g.y_top_m},
                 {"m_per_px", g.m_per_px}, {"width_px", g.width_px}, {"height_px", g.height_px}};
  if (g.valid)  // what the map view shows first: the known part of the map, [[x0, y0], [x1, y1]]
    s.layers["bounds_m"] = {{g.x0_m, g.y_top_m - g.height_px * g.m_per_px},
                            {g.x0_m + g.width_px * g.m_per_px, g.y_top_m}};
  // Unlinked robots' maps as images and, for the operator to align, as points: both walk every cell
  // of each own map, so only full snapshots make them (a quick one keeps the last ones).
  if (options.render_images) {
    s.layers["own_frames"] = nlohmann::json::object();
    for (const RobotFrameMap& m : merged.robot_frame_maps ? *merged.robot_frame_maps : std::vector<RobotFrameMap>{}) {
      s.layers["own_frames"][std::to_string(m.robot.value)] = own_frame_outline(m, options.max_outline_points);
      s.own_maps[std::to_string(m.robot.value)] = render_robot_frame_png(m);
    }
  }
  return s;
}

}  // namespace cairn::base
