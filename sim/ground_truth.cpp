#include "sim/ground_truth.h"

#include <filesystem>
#include <fstream>
#include <iomanip>

#include "common/trajectory.h"

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
         write_robots(sim, (base / "gt_robots.csv").string());
}

}  // namespace cairn::sim
