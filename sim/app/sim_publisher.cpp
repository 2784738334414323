#include "sim/app/sim_publisher.h"

#include <chrono>
#include <thread>

#include "dds/conversions.h"

namespace cairn::sim {

std::unique_ptr<SimPublisher> SimPublisher::create(dds::ParticipantOptions participant,
                                                   const std::vector<RobotId>& robots, std::string* error) {
  std::unique_ptr<SimPublisher> p(new SimPublisher());
  participant.name = "cairn_sim";
  p->participant_ = dds::Participant::create(participant, error);
  if (!p->participant_) return nullptr;
  auto& part = *p->participant_;
  for (RobotId r : robots) {
    RobotWriters w;
    w.robot = r;
    w.odometry = std::make_unique<dds::Writer<dds::OdometryTopic>>(part, r);
    w.laser = std::make_unique<dds::Writer<dds::LaserScanTopic>>(part, r);
    w.rgbd = std::make_unique<dds::Writer<dds::RgbdTopic>>(part, r);
    if (!w.odometry->ok() || !w.laser->ok() || !w.rgbd->ok()) {
      *error = "cannot create sensor writers for " + to_string(r);
      return nullptr;
    }
    p->robots_.push_back(std::move(w));
  }
  p->clock_ = std::make_unique<dds::Writer<dds::ClockTopic>>(part);
  if (!p->clock_->ok()) {
    *error = "cannot create the mission clock writer";
    return nullptr;
  }
  return p;
}

bool SimPublisher::wait_for_agents(double timeout_s, int subscribers) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    bool all = true;
    for (auto& w : robots_) {
      all = all && w.laser->matched_readers() >= subscribers && w.odometry->matched_readers() >= subscribers &&
            w.rgbd->matched_readers() >= subscribers;
    }
    if (all) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

SimPublisher::RobotWriters* SimPublisher::writers_of(RobotId robot) {
  for (auto& w : robots_) {
    if (w.robot == robot) return &w;
  }
  return nullptr;
}

bool SimPublisher::publish(const SimStep& step, std::string* error) {
  auto failed = [&](const char* what, RobotId r) {
    *error = std::string("write of ") + what + " for " + to_string(r) + " timed out";
    return false;
  };
  for (const auto& o : step.odometry) {
    auto* w = writers_of(o.robot);
    if (w && !w->odometry->write(dds::to_msg(o.robot, o.reading))) return failed("odometry", o.robot);
  }
  for (const auto& s : step.scans) {
    auto* w = writers_of(s.robot);
    if (w && !w->laser->write(dds::to_msg(s.robot, s.reading))) return failed("laser scan", s.robot);
  }
  for (const auto& f : step.frames) {
    auto* w = writers_of(f.robot);
    if (w && !w->rgbd->write(dds::to_msg(f.robot, f.reading))) return failed("RGB-D frame", f.robot);
  }
  if (step.stamp_ns >= next_clock_ns_) {
    cairn_msgs::MissionClock clock;
    clock.stamp_ns(step.stamp_ns);
    clock.finished(false);
    clock.robot_count(int32_t(robots_.size()));
    clock_->write(clock);  // best to have, not essential: a lost tick changes nothing
    next_clock_ns_ = step.stamp_ns + kNsPerSec;
  }
  return true;
}

bool SimPublisher::finish(StampNs final_stamp_ns, std::string* error) {
  // A reading written is not a reading delivered: wait for every agent to acknowledge them all
  // before saying the mission is over, so no agent stops with input still in flight.
  for (auto& w : robots_) {
    if (!w.odometry->wait_for_acknowledgments(60) || !w.laser->wait_for_acknowledgments(60) ||
        !w.rgbd->wait_for_acknowledgments(60)) {
      *error = "agent of " + to_string(w.robot) + " did not acknowledge its sensor data within 60 s";
      return false;
    }
  }
  cairn_msgs::MissionClock clock;
  clock.stamp_ns(final_stamp_ns);
  clock.finished(true);
  clock.robot_count(int32_t(robots_.size()));
  if (!clock_->write(clock) || !clock_->wait_for_acknowledgments(30)) {
    *error = "the end-of-mission clock sample was not acknowledged";
    return false;
  }
  return true;
}

}  // namespace cairn::sim
