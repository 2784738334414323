#include "sim/app/sim_commands.h"

#include <chrono>
#include <thread>

#include "dds/navigation_conversions.h"

namespace cairn::sim {

std::unique_ptr<SimCommands> SimCommands::create(dds::Participant& participant, const std::vector<RobotId>& robots,
                                                 std::string* error) {
  std::unique_ptr<SimCommands> c(new SimCommands());
  for (RobotId r : robots) {
    auto reader = std::make_unique<dds::Reader<dds::CmdVelTopic>>(participant, r);
    if (!reader->ok()) {
      *error = "cannot create the cmd_vel reader of " + to_string(r);
      return nullptr;
    }
    c->readers_[r] = std::move(reader);
    c->latest_[r] = StampedCommand{r, -1, {}, false};
    c->silent_[r] = false;
  }
  return c;
}

void SimCommands::poll() {
  std::string error;
  for (auto& [robot, reader] : readers_) {
    for (const auto& m : reader->take_all()) {
      const auto c = dds::from_msg(m, &error);
      if (!c || c->robot != robot) {
        ++bad_;
        CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "dropped a bad command on {}'s cmd_vel: {}",
                              to_string(robot), c ? "robot id of another robot" : error);
        continue;
      }
      if (c->stamp_ns < latest_[robot].stamp_ns) continue;  // an older one, overtaken
      latest_[robot] = *c;
      if (silent_[robot]) log_->info("{}'s agent answers again", to_string(robot));
      silent_[robot] = false;
    }
  }
}

void SimCommands::wait_for_answers(StampNs stamp_ns, const std::vector<RobotId>& scanned, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (true) {
    poll();
    bool all = true;
    for (RobotId robot : scanned) all = all && (silent_[robot] || latest_[robot].stamp_ns >= stamp_ns);
    if (all) return;
    if (std::chrono::steady_clock::now() >= end) break;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  for (RobotId robot : scanned) {
    StampedCommand& c = latest_[robot];
    if (silent_[robot] || c.stamp_ns >= stamp_ns) continue;
    log_->warn("{}'s agent did not answer the scan at {:.1f} s within {} s: it stands still until it does",
               to_string(robot), ns_to_sec(stamp_ns), timeout_s);
    silent_[robot] = true;
    c.command = VelocityCommand{};
  }
}

}  // namespace cairn::sim
