// cairn_bag_from_carmen LOG OUT.mcap: a CARMEN laser log as the ROS 2 bag a real robot would have
// recorded (MCAP, ros2 profile): each laser record becomes a nav_msgs/Odometry on NS/odom (its
// odometry pose) and a sensor_msgs/LaserScan on NS/scan, both stamped with the record's time.
// cairn_replay plays the bag into cairn_agent --ros2: real laser data through the ROS 2 path.
#include <CLI/CLI.hpp>

#include <fstream>

#include "bag/app/ros2_schemas.h"
#include "bag/mcap_writer.h"
#include "common/carmen_log.h"
#include "common/errors.h"
#include "common/logging.h"
#include "dds/cdr.h"
#include "dds/ros2_conversions.h"
#include "ros2_msgsPubSubTypes.h"

int main(int argc, char** argv) {
  CLI::App app{"A CARMEN log as a ROS 2 bag (MCAP): NS/scan and NS/odom"};
  std::string log_path, out_path, ns;
  app.add_option("log", log_path, "CARMEN log (.clf/.log, plain or .gz)")->required();
  app.add_option("out", out_path, "the MCAP file to write")->required();
  app.add_option("--namespace", ns, "ROS 2 namespace of the topics (e.g. robot1)");
  CLI11_PARSE(app, argc, argv);
  auto log = cairn::make_logger("carmen_to_bag");
  cairn::CarmenLog carmen;
  try {
    carmen = cairn::read_carmen_log(log_path);
  } catch (const cairn::InputError& e) {
    log->error("{}", e.what());
    return 2;
  }
  if (cairn::is_corrected_log_name(log_path)) {
    log->error("{} is a corrected log: its odometry is the SLAM result, not what a robot recorded", log_path);
    return 2;
  }
  std::ofstream file(out_path, std::ios::binary | std::ios::trunc);
  if (!file) {
    log->error("{}: cannot be written", out_path);
    return 2;
  }
  const std::string prefix = ns.empty() ? "/" : "/" + ns + "/";
  cairn::bag::McapWriter writer(file);
  const uint16_t scan_schema = writer.add_schema("sensor_msgs/msg/LaserScan", "ros2msg",
                                                 *cairn::bag::ros2msg_schema("sensor_msgs/msg/LaserScan"));
  const uint16_t odom_schema =
      writer.add_schema("nav_msgs/msg/Odometry", "ros2msg", *cairn::bag::ros2msg_schema("nav_msgs/msg/Odometry"));
  const uint16_t scan_channel = writer.add_channel(prefix + "scan", scan_schema, "cdr");
  const uint16_t odom_channel = writer.add_channel(prefix + "odom", odom_schema, "cdr");
  uint32_t seq = 0;
  for (const cairn::CarmenScan& s : carmen.scans) {
    const uint64_t t = uint64_t(s.stamp_ns);
    const auto odom = cairn::dds::to_cdr<nav_msgs::msg::dds_::Odometry_PubSubType>(
        cairn::dds::to_ros(cairn::OdometryReading{s.stamp_ns, s.T_odom_laser, 0.0, 0.0}, "odom", "base_link"));
    auto scan = s.scan;
    scan.stamp_ns = s.stamp_ns;
    const auto laser =
        cairn::dds::to_cdr<sensor_msgs::msg::dds_::LaserScan_PubSubType>(cairn::dds::to_ros(scan, "laser"));
    writer.write(odom_channel, seq, t, t, odom.data(), odom.size());
    writer.write(scan_channel, seq++, t, t, laser.data(), laser.size());
  }
  if (!writer.close()) {
    log->error("{}: writing failed", out_path);
    return 4;
  }
  log->info("{}: {} scans and odometry records -> {} ({:.1f} MB)", log_path, carmen.scans.size(), out_path,
            double(writer.stats().file_bytes) / 1e6);
  return 0;
}
