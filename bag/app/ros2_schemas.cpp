#include "bag/app/ros2_schemas.h"

#include <map>
#include <vector>

namespace cairn::bag {
namespace {

// Each definition with its comments and constants left out; every type fully qualified.
const std::map<std::string, std::string>& definitions() {
  static const std::map<std::string, std::string> d = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/Pose", "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"},
      {"geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/Twist", "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n"},
      {"geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist twist\nfloat64[36] covariance\n"},
      {"sensor_msgs/LaserScan",
       "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
       "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges\n"
       "float32[] intensities\n"},
      {"nav_msgs/Odometry",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
       "geometry_msgs/TwistWithCovariance twist\n"},
  };
  return d;
}

const std::map<std::string, std::vector<std::string>>& dependencies() {
  static const std::map<std::string, std::vector<std::string>> d = {
      {"sensor_msgs/LaserScan", {"std_msgs/Header", "builtin_interfaces/Time"}},
      {"nav_msgs/Odometry",
       {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose",
        "geometry_msgs/Point", "geometry_msgs/Quaternion", "geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist",
        "geometry_msgs/Vector3"}},
      {"geometry_msgs/Twist", {"geometry_msgs/Vector3"}},
  };
  return d;
}

}  // namespace

std::optional<std::string> ros2msg_schema(const std::string& ros_type) {
  // "sensor_msgs/msg/LaserScan" -> "sensor_msgs/LaserScan"
  const auto slash = ros_type.find("/msg/");
  if (slash == std::string::npos) return std::nullopt;
  const std::string short_name = ros_type.substr(0, slash) + "/" + ros_type.substr(slash + 5);
  const auto deps = dependencies().find(short_name);
  if (deps == dependencies().end()) return std::nullopt;
  std::string text = definitions().at(short_name);
  for (const std::string& dep : deps->second) {
    text += std::string(80, '=') + "\nMSG: " + dep + "\n" + definitions().at(dep);
  }
  return text;
}

}  // namespace cairn::bag
