#include "sim/ground_truth.h"

#include <filesystem>
#include <fstream>
#include <iomanip>

#include "common/trajectory.h"
#include "sim/reachable_area.h"

namespace cairn::sim {
namespace {

bool write_objects(const std::vector<WorldObject>& objects, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out << "id,class,shape,x_m,y_m,z_m,yaw_rad,size_x,size_y,size_z,r,g,b\n" << std::setprecision(9);
  for (const WorldObject& o : objects) {
    out << o.id << ',' << o.object_class << ',' << to_string(o.shape) << ',' << o.center_m.x() << ',' << o.center_m.y()
        << ',' << o.center_m.z() << ',' << o.yaw_rad << ',' << o.size_m.x() << ',' << o.size_m.y() << ','
        << o.size_m.z() << ',' << int(o.color_rgb[0]) << ',' << int(o.color_rgb[1]) << ',' << int(o.color_rgb[2])
        << '\n';
  }
  out.flush();
  return bool(out);
}

bool write_robots(const Simulator& sim, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out << "id,start_x,start_y,start_yaw\n" << std::setprecision(12);
  for (RobotId id : sim.robot_ids()) {
    const SE2 s = sim.T_world_start(id);
    out << id.value << ',' << s.x() << ',' << s.y() << ',' << s.yaw() << '\n';
  }
  out.flush();
  return bool(out);
}

/// gt_motion.csv: per robot, the distance it drove (from its true trajectory) and its collisions.
bool write_motion(const Simulator& sim, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out << "id,distance_m,collisions\n" << std::setprecision(9);
  for (RobotId id : sim.robot_ids()) {
    const Trajectory& t = sim.ground_truth(id);
    double distance_m = 0;
    for (size_t i = 1; i < t.size(); ++i) distance_m += (t[i].pose.translation() - t[i - 1].pose.translation()).norm();
    out << id.value << ',' << distance_m << ',' << sim.collisions(id) << '\n';
  }
  out.flush();
  return bool(out);
}

/// gt_reachable.pgm (255: a free cell connected to a robot's start, top row first as map_server
/// images) and gt_reachable.yaml (resolution, origin): the explorable area, for coverage scores.
bool write_reachable(const Simulator& sim, const std::filesystem::path& base) {
  const FloorPlan& plan = sim.world().floor_plan;
  std::vector<Eigen::Vector2d> starts;
  for (RobotId id : sim.robot_ids()) starts.push_back(sim.T_world_start(id).translation());
  const std::vector<uint8_t> reached = reachable_free_cells(plan, starts);
  std::ofstream pgm(base / "gt_reachable.pgm", std::ios::binary);
  pgm << "P5\n" << plan.width() << ' ' << plan.height() << "\n255\n";
  for (int r = plan.height() - 1; r >= 0; --r) {
    for (int c = 0; c < plan.width(); ++c)
      pgm.put(reached[size_t(r) * size_t(plan.width()) + size_t(c)] ? char(255) : 0);
  }
  pgm.flush();
  std::ofstream yaml(base / "gt_reachable.yaml");
  yaml << std::setprecision(12) << "image: gt_reachable.pgm\nresolution: " << plan.resolution_m() << "\norigin: ["
       << plan.origin_m().x() << ", " << plan.origin_m().y() << ", 0.0]\n";
  yaml.flush();
  return bool(pgm) && bool(yaml);
}

}  // namespace

bool write_ground_truth(const Simulator& sim, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) return false;
  const std::filesystem::path base(dir);
  for (RobotId id : sim.robot_ids()) {
    const std::string path = (base / ("gt_robot" + std::to_string(id.value) + ".csv")).string();
    if (!write_trajectory_csv(path, sim.ground_truth(id))) return false;
  }
  return write_objects(sim.objects(), (base / "gt_objects.csv").string()) &&
         write_robots(sim, (base / "gt_robots.csv").string()) && write_motion(sim, (base / "gt_motion.csv").string()) &&
         write_reachable(sim, base);
}

}  // namespace cairn::sim
