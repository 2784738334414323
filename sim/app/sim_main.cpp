// cairn_sim: runs a simulated mission and publishes each robot's sensors on DDS, as robot drivers
// would. Data flow: World (YAML + floor plan) -> sim::Simulator::step() -> SimPublisher -> DDS.
// At the end it writes ground truth and announces the end of the mission on the clock topic.
// With --radio FILE it also evaluates each robot's radio link (sim/radio_model.h) at the robots'
// true positions and appends it to FILE, for the mission tool to cut and restore the links.
#include <CLI/CLI.hpp>

#include <chrono>
#include <fstream>
#include <thread>

#include "common/errors.h"
#include "common/logging.h"
#include "sim/app/sim_commands.h"
#include "sim/app/sim_publisher.h"
#include "sim/ground_truth.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace {

/// Appends every robot's link when the radio's period is due; logs each cut and restore.
void write_radio(const cairn::sim::Simulator& sim, cairn::sim::RadioLinks& radio, std::ofstream& out,
                 spdlog::logger& log) {
  std::vector<std::pair<cairn::RobotId, Eigen::Vector2d>> robots_m;
  for (cairn::RobotId robot : sim.robot_ids()) robots_m.push_back({robot, sim.true_pose(robot).translation()});
  for (const cairn::sim::RadioSample& s : radio.update(sim.now_ns(), robots_m)) {
    out << cairn::ns_to_sec(s.stamp_ns) << ',' << s.robot.value << ',' << s.reading.received_dbm << ','
        << s.reading.walls << ',' << (s.up ? 1 : 0) << '\n';
    if (s.changed) {
      log.info("radio link of robot {} {} at t = {:.1f} s ({:.0f} dBm, {} walls)", s.robot.value, s.up ? "back" : "cut",
               cairn::ns_to_sec(s.stamp_ns), s.reading.received_dbm, s.reading.walls);
    }
  }
  out.flush();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn multi-robot simulator"};
  std::string world_path, routes_path, out_dir, radio_path, log_level = "info";
  cairn::dds::ParticipantOptions participant;
  participant.same_host_only = true;  // the robots' onboard sensor buses never cross the radio
  double speed = 0.0, wait_agents_s = 30.0, duration_s = 0.0, answer_timeout_s = 10.0;
  int64_t seed = -1;
  int subscribers = 1;
  app.add_option("--world", world_path, "world YAML file")->required();
  app.add_option("--routes", routes_path,
                 "scripted routes YAML (routes: - {robot: N, waypoints: [[x, y], ...]}): the robots drive them "
                 "instead of obeying velocity commands");
  app.add_option("--out", out_dir, "ground-truth output folder")->required();
  app.add_option("--domain", participant.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--security", participant.security_dir,
                 "DDS Security: folder with ca.pem, cert.pem, key.pem (deploy/security/make_certs.sh)");
  app.add_option("--speed", speed, "times real time (0 = as fast as the agents take it)");
  app.add_option("--seed", seed, "override the world's random seed");
  app.add_option("--duration", duration_s, "override the mission duration [s]");
  app.add_option("--wait-agents", wait_agents_s, "seconds to wait for every robot's agent");
  app.add_option("--subscribers", subscribers,
                 "subscribers each robot's sensor topics must have before the mission starts (2 with a recorder)")
      ->check(CLI::Range(1, 16));
  app.add_option("--answer-timeout", answer_timeout_s,
                 "lock-step (--speed 0, command mode): seconds to wait for an agent's command answering a scan");
  app.add_option("--radio", radio_path,
                 "CSV file to append each robot's simulated radio link to (t_s,robot,received_dbm,walls,up), every "
                 "radio.period_s of the world");
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("sim");

  cairn::sim::WorldFile wf;
  try {
    cairn::sim::WorldLoadOptions load;
    load.routes_path = routes_path;
    wf = cairn::sim::load_world_file(world_path, load);
  } catch (const cairn::InputError& e) {
    log->error("{}", e.what());
    return 2;
  }
  if (seed >= 0) wf.sim.seed = uint64_t(seed);
  if (duration_s > 0) wf.sim.duration_s = duration_s;
  cairn::sim::Simulator sim(wf.world, wf.sim);

  std::string error;
  auto publisher = cairn::sim::SimPublisher::create(participant, sim.robot_ids(), &error);
  if (!publisher) {
    log->error("{}", error);
    return 3;
  }
  log->info("world '{}' with {} robots (drive: {}), {} objects; waiting for agents on domain {}", wf.world.name,
            sim.robot_ids().size(), cairn::sim::to_string(wf.sim.drive_mode), wf.world.objects.size(),
            participant.domain_id);
  // Command mode: each robot obeys its agent's cairn/robot<N>/cmd_vel. With --speed 0 the
  // simulator runs in lock-step: after each step with laser scans it waits for every agent's
  // command answering them, so the motion does not depend on how fast the processes run.
  std::unique_ptr<cairn::sim::SimCommands> commands;
  if (sim.drive_mode() == cairn::sim::DriveMode::kCommands) {
    commands = cairn::sim::SimCommands::create(publisher->participant(), sim.robot_ids(), &error);
    if (!commands) {
      log->error("{}", error);
      return 3;
    }
  }
  if (!publisher->wait_for_agents(wait_agents_s, subscribers)) {
    log->error("not every robot's agent subscribed within {} s", wait_agents_s);
    return 4;
  }

  std::ofstream radio_out;
  cairn::sim::RadioLinks radio(sim.world().floor_plan, sim.world().radio);
  if (!radio_path.empty()) {
    radio_out.open(radio_path, std::ios::trunc);
    if (!(radio_out << "t_s,robot,received_dbm,walls,up\n" << std::flush)) {
      log->error("cannot write the radio links to '{}'", radio_path);
      return 2;
    }
  }

  const auto wall_start = std::chrono::steady_clock::now();
  while (!sim.done()) {
    if (radio_out.is_open()) write_radio(sim, radio, radio_out, *log);
    const cairn::sim::SimStep step = sim.step();
    if (!publisher->publish(step, &error)) {
      log->error("publishing at t={:.2f} s failed: {}", cairn::ns_to_sec(step.stamp_ns), error);
      return 5;
    }
    if (speed > 0) {
      std::this_thread::sleep_until(wall_start + std::chrono::nanoseconds(int64_t(step.stamp_ns / speed)));
    }
    if (commands) {
      if (speed <= 0 && !step.scans.empty()) {
        std::vector<cairn::RobotId> scanned;
        for (const auto& s : step.scans) scanned.push_back(s.robot);
        commands->wait_for_answers(step.stamp_ns, scanned, answer_timeout_s);
      } else {
        commands->poll();
      }
      for (cairn::RobotId robot : sim.robot_ids()) {
        const cairn::StampedCommand& c = commands->latest(robot);
        sim.set_command(robot, c.command);  // the simulator clamps it to the robot's limits
        sim.set_robot_done(robot, c.done);
      }
    }
    CAIRN_LOG_EVERY_N_SEC(log, spdlog::level::info, 5.0, "t = {:.1f} s", cairn::ns_to_sec(step.stamp_ns));
  }
  if (!cairn::sim::write_ground_truth(sim, out_dir)) {
    log->error("cannot write ground truth into '{}'", out_dir);
    return 6;
  }
  if (!publisher->finish(sim.now_ns(), &error)) {
    log->error("{}", error);
    return 7;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  log->info("mission over: {:.1f} s simulated in {:.1f} s wall; ground truth in {}", cairn::ns_to_sec(sim.now_ns()),
            wall_s, out_dir);
  return 0;
}
