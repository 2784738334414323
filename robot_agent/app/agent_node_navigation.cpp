// AgentNode's navigation part: each processed scan drives the robot. MissionBehaviour decides
// what to drive to (the base's goals, its own map's frontiers, home), Navigator plans and steers,
// and the command answering the scan goes out on cairn/robot<N>/cmd_vel, stamped with the scan's
// stamp (the simulator's lock-step waits for it). The operator's commands (OperatorOrders) outrank
// MissionBehaviour until the operator resumes the robot. Data flow:
//   AgentOutputs::scans -> MissionBehaviour::update -> Navigator::set_goal / update -> cmd_vel
//   cairn/goal -> take_goal -> MissionBehaviour::on_base_goal;  cairn/ack -> on_contact
//   cairn/operator_command -> take_command -> OperatorOrders -> apply_operator_action -> Navigator
//   cairn/keep_out -> take_keep_out -> Navigator (every plan) and nearest_own_frontier
#include "dds/navigation_conversions.h"
#include "robot_agent/app/agent_node.h"

namespace cairn::agent {
namespace {

/// Decisions wait until the robot's own map holds this many scans: on an empty map every robot
/// would find "no frontier left" and go home.
constexpr int kScansBeforeDeciding = 5;

}  // namespace

void AgentNode::take_goal(const cairn_msgs::ExplorationGoal& m) {
  std::string error;
  const auto goal = dds::from_msg(m, &error);
  if (!goal) {
    ++bad_samples_;
    log_->warn("dropped a goal from the base: {}", error);
    return;
  }
  behaviour_.on_base_goal({goal->goal_id, goal->kind, goal->has_goal, goal->goal_m}, last_scan_ns_,
                          pose_.translation());
}

void AgentNode::take_command(const cairn_msgs::OperatorCommand& m) {
  std::string error;
  const auto command = dds::from_msg(m, &error);
  if (!command) {
    ++bad_samples_;
    log_->warn("dropped an operator command: {}", error);
    return;
  }
  heard_from_base();
  if (operator_.take(*command)) {
    log_->info("operator command {}: {} ({:.1f}, {:.1f}) m", command->seq, to_string(command->kind),
               command->goal_m.x(), command->goal_m.y());
  }
}

void AgentNode::take_keep_out(const cairn_msgs::KeepOutAreas& m) {
  std::string error;
  auto message = dds::from_msg(m, &error);
  if (!message) {
    ++bad_samples_;
    log_->warn("dropped keep-out areas from the base: {}", error);
    return;
  }
  heard_from_base();
  // Taken even when the version is the one held: a restarted base counts versions from 1 again, and
  // a resend (the base did not hear this robot hold it) only costs one re-plan.
  if (message->version != keep_out_version_) {
    log_->info("keep-out areas: {} (version {})", message->areas.size(), message->version);
  }
  keep_out_version_ = message->version;
  navigator_.set_keep_out(std::move(message->areas));
}

void AgentNode::apply_operator_action() {
  switch (operator_.next_action()) {
    case OperatorAction::kNone:
      return;
    case OperatorAction::kDriveTo:
      navigator_.set_goal(NavGoal{0, operator_.goal_m(), GoalKind::kOwn, 0, {}});
      reported_goal_ = {0, GoalKind::kOwn, RobotActivity::kOperatorGoal, operator_.goal_m()};
      reported_state_ = NavState::kDriving;
      return;
    case OperatorAction::kHold:
      navigator_.cancel();
      return;
    case OperatorAction::kGoHome:
      behaviour_.on_base_goal({0, GoalKind::kHome, true, Eigen::Vector2d::Zero()}, last_scan_ns_, pose_.translation());
      [[fallthrough]];
    case OperatorAction::kRelease:
      // Autonomy again: MissionBehaviour's target (if it has one) is driven anew; otherwise it
      // chooses at this scan.
      if (const auto& t = behaviour_.target()) {
        navigator_.set_goal(NavGoal{t->goal_id, t->position_m, t->kind, t->tolerance_m, {}});
      } else {
        navigator_.cancel();
      }
      return;
  }
}

void AgentNode::heard_from_base() { behaviour_.on_contact(last_scan_ns_, pose_.translation()); }

void AgentNode::drive(const AgentOutputs& outputs) {
  if (pipeline_.laser_lost() && !behaviour_.laser_lost()) {
    behaviour_.on_laser_lost();
    log_->warn(
        "laser silent: poses and keyframes from odometry alone; it explores no further and goes home by the "
        "map it has");
  }
  // A scan that ends dead reckoning is among this call's processed scans: no stats copy on idle polls.
  if (const int back = outputs.scans.empty() ? last_laser_recoveries_ : pipeline_.stats().laser_recoveries;
      back > last_laser_recoveries_) {
    last_laser_recoveries_ = back;
    log_->warn(
        "laser back: scan matching again; still going home (a laser that failed once is not trusted to explore; "
        "the operator can send the robot out again)");
  }
  if (!options_.navigate || outputs.scans.empty()) return;
  VelocityCommand command;
  for (const PosedScan& ps : outputs.scans) {
    if (last_scan_ns_ >= 0) distance_m_ += (ps.T_local_base.translation() - pose_.translation()).norm();
    pose_ = ps.T_local_base;
    last_scan_ns_ = ps.scan.stamp_ns;
    breadcrumbs_.add(pose_.translation());
    const OwnFrontierSearch own_frontier = [&](const std::vector<Eigen::Vector2d>& blacklist_m) {
      const auto f = nearest_own_frontier(navigator_.map().grid(), pose_.translation(), blacklist_m, own_options_,
                                          navigator_.keep_out());
      return f ? std::optional<Eigen::Vector2d>(f->goal_m) : std::nullopt;
    };
    // Map and steer first, then decide: the decision sees this scan in the map and the goal's
    // newest state; a new goal is driven from the next scan on (100 ms later at 10 Hz).
    apply_operator_action();
    const NavState before = navigator_.state();
    command = navigator_.update(last_scan_ns_, pose_, ps.scan);
    if (navigator_.goal()) reported_state_ = navigator_.state();  // an ended goal's state stays until the next
    if (navigator_.state() != before && navigator_.state() != NavState::kDriving) {
      log_->info("goal {}: {}", to_string(navigator_.state()), navigator_.reason());
    }
    if (operator_.in_control()) {
      operator_.on_navigation(navigator_.state(), navigator_.reason());
      if (operator_.holding()) command = VelocityCommand{};
      continue;  // the operator decides, not MissionBehaviour
    }
    operator_.on_home(behaviour_.done());
    if (navigator_.map().scans_inserted() < kScansBeforeDeciding) continue;
    if (const auto target = behaviour_.update(last_scan_ns_, pose_.translation(), navigator_.state(), own_frontier)) {
      NavGoal goal{target->goal_id, target->position_m, target->kind, target->tolerance_m, {}};
      const bool going_back =
          target->activity == RobotActivity::kGoingHome || target->activity == RobotActivity::kReturningToContact;
      if (going_back) goal.fallback_path_m = breadcrumbs_.way(pose_.translation(), target->position_m);
      if (target->activity == RobotActivity::kGoingHome) goal.settle_within_m = options_.behaviour.home_area_m;
      navigator_.set_goal(goal);
      reported_goal_ = *target;
      reported_state_ = NavState::kDriving;
      log_->info("{}: goal ({:.1f}, {:.1f}) m{} ({})", to_string(target->activity), target->position_m.x(),
                 target->position_m.y(), target->goal_id ? " from the base, id " + std::to_string(target->goal_id) : "",
                 behaviour_.reason());
    } else if (!behaviour_.target() && navigator_.goal()) {
      navigator_.cancel();
      command = VelocityCommand{};
    }
    if (behaviour_.activity() != last_activity_) {
      if (behaviour_.done()) log_->info("mission over: {}", behaviour_.reason());
      last_activity_ = behaviour_.activity();
    }
    if (behaviour_.done()) command = VelocityCommand{};
  }
  cmd_out_->write(dds::to_msg(StampedCommand{robot_, last_scan_ns_, command, behaviour_.done()}));
  if (ros2_in_) ros2_in_->send_cmd_vel(command.linear_mps, command.angular_radps);
}

NavStatus AgentNode::nav_status() const {
  NavStatus n;
  n.pose = pose_;
  n.activity = operator_.in_control() ? operator_.activity() : behaviour_.activity();
  // The newest goal and its state, also once it ended: the base learns from it that its goal was
  // reached or failed (and blacklists a failed one).
  n.nav_state = reported_state_;
  n.goal_id = reported_goal_.goal_id;
  n.goal_kind = reported_goal_.kind;
  n.goal_m = reported_goal_.position_m;
  n.distance_m = distance_m_;
  n.command = operator_.report();
  n.keep_out_version = keep_out_version_;
  n.path_m = navigator_.path_ahead(kMaxStatusPathPoints);
  return n;
}

}  // namespace cairn::agent
