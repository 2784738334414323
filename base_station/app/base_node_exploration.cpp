// BaseNode's exploration part: the robots' navigation states in (cairn/status), the team's plan
// (plan_exploration) and each robot's order (GoalAllocator) out on cairn/goal, in its own frame.
#include "base_station/app/base_node.h"
#include "base_station/core/active_linking.h"
#include "base_station/core/merged_map.h"
#include "base_station/core/saliency_layer.h"
#include "dds/navigation_conversions.h"

namespace cairn::base {

void BaseNode::note_navigation(const NavStatus& nav, RobotId robot, bool live) {
  const auto before = navigation_.find(robot);
  if (live && (before == navigation_.end() || before->second.activity != nav.activity)) {
    log_->info("{} is {}", sessions_.label(robot), to_string(nav.activity));
  }
  navigation_[robot] = nav;
  note_command_report(robot, nav.command, live);
  const int blacklisted = goals_.goals_blacklisted();
  const auto order = goals_.orders().find(robot);
  const bool meeting_failed = order != goals_.orders().end() && order->second.kind == GoalKind::kMeet &&
                              order->second.goal_id == nav.goal_id &&
                              (nav.nav_state == NavState::kUnreachable || nav.nav_state == NavState::kStuck);
  if (meeting_failed) {
    const auto placed = [this](RobotId r) { return mapper_.linked(r); };
    if (const auto event = meetings_.goal_failed(robot, mapper_.data().latest_stamp_ns, placed)) {
      report_meeting(*event, live);
    }
  }
  if (goals_.report({robot, nav.goal_id, nav.nav_state, nav.activity}, mapper_.data().latest_stamp_ns)) {
    replan_now_ = true;  // its order is over: plan again at the next optimise tick
  }
  if (live && goals_.goals_blacklisted() > blacklisted) {
    log_->info("{} could not reach goal {} ({}): not sent again for a while", sessions_.label(robot), nav.goal_id,
               to_string(nav.nav_state));
  }
}

void BaseNode::plan_and_publish_goals(bool send) {
  const MergedMap merged = mapper_.merged();
  const StampNs now_ns = merged.data->latest_stamp_ns;
  // Where the linked robots are: their newest reported pose, else their newest keyframe.
  std::map<RobotId, Eigen::Vector2d> robots_m;
  std::map<RobotId, std::optional<SE2>> placements = merged.placements();
  for (const RobotSummary& r : merged.robots) {
    if (!r.linked) continue;
    if (!sessions_.is_current(r.id)) {  // a session that ended (the robot restarted): nothing drives it
      placements.erase(r.id);
      goals_.release(r.id);
      continue;
    }
    if (commands_.under_operator(r.id)) {  // the operator decides where it goes: no orders, no share of goals
      placements.erase(r.id);
      goals_.release(r.id);
      continue;
    }
    // Not one keyframe of it on the map yet (its start given, its sensors not started): nothing to
    // plan on, and an empty map must not read as "no frontier left, go home".
    const Trajectory& trajectory = merged.trajectory(r.id);
    if (trajectory.empty()) continue;
    const auto nav = navigation_.find(r.id);
    if (nav != navigation_.end()) {
      robots_m[r.id] = r.T_global_local * nav->second.pose.translation();
    } else {
      robots_m[r.id] = trajectory.back().pose.translation();
    }
  }
  // Robots not placed after a while go to meet a placed teammate (active linking); the teammates
  // driving to a meeting are left out of the exploration plan.
  const std::map<RobotId, MeetGoal> meet = plan_meetings(merged, placements, robots_m, send);
  for (const RobotId teammate : meetings_.moving_teammates()) robots_m.erase(teammate);
  if (robots_m.empty() && meet.empty()) {  // nothing placed (or all driven by the operator) to plan for
    plan_.goals.clear();                   // no stale "next" goal on the map
    plan_.meetings.clear();
    return;
  }
  std::vector<Eigen::Vector2d> victims_m;
  for (const GlobalObject& o : merged.objects) {
    if (o.class_name == "victim") victims_m.push_back(o.position_m.head<2>());
  }
  std::vector<Eigen::Vector2d> objects_m;
  for (const GlobalObject& o : merged.objects) objects_m.push_back(o.position_m.head<2>());
  auto saliency =
      std::make_shared<const SaliencyLayer>(build_saliency_layer(*merged.data, now_ns, objects_m, options_.saliency));
  ExplorationContext context;
  context.blacklist_m = goals_.blacklist_m(now_ns);
  context.current_goals_m = goals_.current_goals_m();
  context.saliency = saliency.get();
  context.keep_out = search_.keep_out();
  plan_ = plan_exploration(*merged.grid, robots_m, victims_m, options_.exploration, context);
  plan_.saliency = std::move(saliency);
  for (const auto& [robot, m] : meetings_.meetings()) {  // shown on the console's map and goal list
    plan_.meetings.push_back({robot, m.teammate, m.robot_goal_global_m});
    if (m.teammate_goal_m && meet.count(m.teammate))
      plan_.meetings.push_back({m.teammate, robot, meet.at(m.teammate).global_m});
  }
  planned_version_ = mapper_.version();
  replan_now_ = false;
  if (!send || search_.paused()) return;  // paused: the plan is shown, no robot is sent
  const bool was_home = goals_.sent_home();
  CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::info, 10.0, "exploration: {} frontiers, {} goals for {} placed robots",
                        plan_.frontiers.size(), plan_.goals.size(), robots_m.size());
  for (const GoalOrder& order : goals_.assign(plan_, placements, now_ns, meet)) {
    GoalMessage msg;
    msg.robot = order.robot;
    msg.goal_id = order.goal_id;
    msg.kind = order.kind;
    msg.has_goal = order.kind != GoalKind::kOwn;
    msg.goal_m = order.goal_local_m;
    msg.path_m = order.path_m;
    msg.frontier_m = order.frontier_m;
    cairn_msgs::ExplorationGoal out = dds::to_msg(msg);
    if (address(order.robot, &out)) goal_out_->write(out);  // to the robot id and session on the wire
  }
  if (goals_.sent_home() && !was_home) log_->info("no reachable frontier left: every placed robot is sent home");
}

std::map<RobotId, MeetGoal> BaseNode::plan_meetings(const MergedMap& merged,
                                                    const std::map<RobotId, std::optional<SE2>>& placements,
                                                    const std::map<RobotId, Eigen::Vector2d>& placed_m, bool send) {
  std::vector<UnlinkedRobot> unlinked;
  for (const RobotSummary& r : merged.robots) {
    const auto nav = navigation_.find(r.id);
    if (r.linked || r.keyframes == 0 || !sessions_.is_current(r.id) || commands_.under_operator(r.id) ||
        nav == navigation_.end())
      continue;
    UnlinkedRobot u{r.id, r.first_stamp_ns, nav->second.pose, std::nullopt};
    // The guess of its placement: the operator's alignment while it is judged, or refused only for
    // want of overlap; else the entry hint.
    const auto alignment = merged.alignments.find(r.id);
    const auto hint = merged.data->entry_hints.find(r.id);
    if (alignment != merged.alignments.end() &&
        (alignment->second.state == AlignmentState::kPending || alignment->second.plausible)) {
      u.hypothesis = LinkHypothesis{alignment->second.requested, "the operator's alignment"};
    } else if (hint != merged.data->entry_hints.end()) {
      u.hypothesis = LinkHypothesis{hint->second.T_global_local, "its entry hint"};
    }
    unlinked.push_back(u);
  }
  std::map<RobotId, MeetGoal> meet;
  if (!send || search_.paused()) return meet;  // no orders go out: no meeting starts either
  // They have met when they can see each other: no wall between them on the global map.
  const LineOfSight in_sight = [&merged](const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) {
    return merged.grid->line_clear(a_m, b_m);
  };
  for (const MeetingEvent& event : meetings_.update(unlinked, placed_m, merged.data->latest_stamp_ns, in_sight)) {
    report_meeting(event, true);
  }
  for (const auto& [robot, m] : meetings_.meetings()) {
    meet[robot] = {m.robot_goal_global_m, m.robot_goal_local_m};
    const auto placement = placements.find(m.teammate);
    if (m.teammate_goal_m && placement != placements.end() && placement->second) {
      meet[m.teammate] = {*m.teammate_goal_m, placement->second->inverse() * *m.teammate_goal_m};
    }
  }
  return meet;
}

void BaseNode::report_meeting(const MeetingEvent& event, bool live) {
  if (!live) return;
  const Meeting& m = event.meeting;
  const std::string robot = sessions_.label(m.robot), teammate = sessions_.label(m.teammate);
  switch (event.kind) {
    case MeetingEvent::Kind::kStarted:
      log_->info("{} not on the map {:.0f} s after its first keyframe: sent to meet {} ({:.1f} m away by {})", robot,
                 ns_to_sec(m.started_ns - m.first_keyframe_ns), teammate, m.distance_m, m.hypothesis.source);
      break;
    case MeetingEvent::Kind::kLinked:
      log_->info("{} linked while meeting {}", robot, teammate);
      break;
    case MeetingEvent::Kind::kFailed:
      log_->info("{}'s meeting with {} given up: {}; not sent again for {:.0f} s", robot, teammate, event.why,
                 meetings_.options().retry_s);
      break;
  }
}

}  // namespace cairn::base

namespace cairn::base {

void BaseNode::record_coverage(const MergedMap& merged) {
  const OccupancyGrid& grid = *merged.grid;
  int free_cells = 0;
  for (int r = 0; r < grid.height(); ++r) {
    for (int c = 0; c < grid.width(); ++c) free_cells += grid.known(c, r) && grid.probability(c, r) < 0.25;
  }
  double frontier_m = 0;
  for (const Frontier& f : plan_.frontiers) frontier_m += f.length_m;
  int victims = 0;
  for (const GlobalObject* o : merged.all_objects()) victims += o->class_name == "victim";
  const double t_s = ns_to_sec(merged.data->latest_stamp_ns);
  if (!coverage_series_.empty() && coverage_series_.back()["t_s"].get<double>() >= t_s)
    coverage_series_.erase(coverage_series_.size() - 1);
  coverage_series_.push_back({{"t_s", t_s},
                              {"free_m2", free_cells * grid.resolution_m() * grid.resolution_m()},
                              {"known_m2", grid.known_area_m2()},
                              {"frontier_m", frontier_m},
                              {"victims", victims}});
}

void BaseNode::add_navigation_json(RobotId robot, nlohmann::json* link) const {
  const auto it = navigation_.find(robot);
  if (it == navigation_.end()) return;
  const NavStatus& n = it->second;
  (*link)["activity"] = to_string(n.activity);
  (*link)["nav_state"] = to_string(n.nav_state);
  (*link)["goal_id"] = n.goal_id;
  (*link)["goal_kind"] = to_string(n.goal_kind);
  (*link)["distance_m"] = n.distance_m;
  (*link)["pose_local"] = {n.pose.x(), n.pose.y(), n.pose.yaw()};
  nlohmann::json path = nlohmann::json::array();  // the path it is driving, ahead of it, own frame
  for (const Eigen::Vector2d& p : n.path_m) path.push_back({p.x(), p.y()});
  (*link)["path_local"] = path;
  // The keep-out areas the robot's own planner obeys: the version it holds, and the newest sent.
  (*link)["keep_out_held"] = n.keep_out_version;
  (*link)["keep_out_sent"] = keep_out_relay_.sent_version(robot);
}

}  // namespace cairn::base
