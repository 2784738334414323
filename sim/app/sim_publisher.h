#pragma once
// The simulator's DDS side: one odometry, laser and RGB-D writer per robot, plus the mission clock.
#include <memory>
#include <string>
#include <vector>

#include "dds/endpoints.h"
#include "sim/simulator.h"

namespace cairn::sim {

class SimPublisher {
 public:
  /// `participant`: domain, peers and security; its name is set here.
  static std::unique_ptr<SimPublisher> create(dds::ParticipantOptions participant, const std::vector<RobotId>& robots,
                                              std::string* error);
  /// True once every robot's sensor topics have `subscribers` subscribers each (its agent, and a
  /// recorder when one runs: a recorder alone must not start the mission before the agents).
  bool wait_for_agents(double timeout_s, int subscribers = 1);
  /// Publishes one step's readings (and the clock once per simulated second).
  bool publish(const SimStep& step, std::string* error);
  /// Waits until the agents acknowledged every reading, then announces the end of the mission.
  bool finish(StampNs final_stamp_ns, std::string* error);
  dds::Participant& participant() { return *participant_; }

 private:
  struct RobotWriters {
    RobotId robot;
    std::unique_ptr<dds::Writer<dds::OdometryTopic>> odometry;
    std::unique_ptr<dds::Writer<dds::LaserScanTopic>> laser;
    std::unique_ptr<dds::Writer<dds::RgbdTopic>> rgbd;
  };
  RobotWriters* writers_of(RobotId robot);

  std::unique_ptr<dds::Participant> participant_;
  std::vector<RobotWriters> robots_;
  std::unique_ptr<dds::Writer<dds::ClockTopic>> clock_;
  StampNs next_clock_ns_ = 0;
};

}  // namespace cairn::sim
