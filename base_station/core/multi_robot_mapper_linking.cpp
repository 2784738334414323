// MultiRobotMapper: automatic linking of robots with unknown relative starts, and the incremental
// pose-graph update (see multi_robot_mapper.h).
#include <Eigen/Cholesky>
#include <algorithm>
#include <deque>
#include <set>

#include "base_station/core/multi_robot_mapper.h"

namespace cairn::base {
LoopClosure reversed(const LoopClosure& c) {
  LoopClosure o{c.b, c.a, c.T_a_b.inverse(), c.covariance, c.score};
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() = o.T_a_b.rotation();
  o.covariance = R * c.covariance * R.transpose();
  return o;
}

PoseGraphEdge loop_edge(const LoopClosure& c) {
  Eigen::LLT<Eigen::Matrix3d> llt(0.5 * (c.covariance + c.covariance.transpose()));
  const Eigen::Matrix3d information = llt.info() == Eigen::Success
                                          ? Eigen::Matrix3d(llt.solve(Eigen::Matrix3d::Identity()))
                                          : Eigen::Matrix3d::Identity();
  return PoseGraphEdge{c.a, c.b, c.T_a_b, information, EdgeKind::kLoop};
}

void MultiRobotMapper::choose_anchor() {
  if (anchor_committed_ || keyframes_.empty()) return;
  if (!hints_.empty()) {
    anchor_ = hints_.begin()->first;
  } else {
    anchor_ = keyframes_.begin()->first.robot;  // lowest id seen
    starts_[*anchor_] = SE2();
  }
  anchor_committed_ = true;
}

RobotId MultiRobotMapper::component_of(RobotId robot) const {
  // Hinted robots and the anchor share the anchor's component.
  if (anchor_ && (hints_.count(robot) || robot == *anchor_)) robot = *anchor_;
  auto it = component_parent_.find(robot);
  while (it != component_parent_.end() && it->second != robot) {
    robot = it->second;
    it = component_parent_.find(robot);
  }
  return robot;
}

void MultiRobotMapper::detect_new_loops(OptimizeResult* result) {
  for (KeyframeId id : detect_queue_) {
    for (const LoopClosure& c : loop_closer_.add_and_detect(keyframes_.at(id), keyframes_)) {
      if (c.a.robot == c.b.robot || component_of(c.a.robot) == component_of(c.b.robot)) {
        // Intra-robot: must agree with the robot's own poses up to its drift; a pair already
        // linked: a closure that would move a linked robot must pass the map check first.
        if (accept_linked_pair_closure(c, result)) loops_.push_back(c);
      } else {
        const auto key = std::minmax(c.a.robot, c.b.robot);
        // Orient every candidate of a pair the same way (a = lower robot id) for PCM.
        inter_candidates_[{key.first, key.second}].push_back(c.a.robot == key.first ? c : reversed(c));
      }
    }
  }
  detect_queue_.clear();
  for (const auto& [pair, list] : inter_candidates_) result->pending_candidates += int(list.size());
}

void MultiRobotMapper::link_robot_pairs(OptimizeResult* result) {
  for (auto it = inter_candidates_.begin(); it != inter_candidates_.end();) {
    const auto [ra, rb] = it->first;
    if (component_of(ra) == component_of(rb)) {  // linked through a third robot meanwhile
      for (const LoopClosure& c : it->second) {
        if (accept_linked_pair_closure(c, result)) loops_.push_back(c);
      }
      it = inter_candidates_.erase(it);
      continue;
    }
    if (try_link_pair(ra, rb, &it->second, result)) {
      it = inter_candidates_.erase(it);
    } else {
      ++it;
    }
  }
}

void MultiRobotMapper::refresh_own_frames() {
  std::map<RobotId, std::vector<const LoopClosure*>> own_loops;
  for (const LoopClosure& c : loops_) {
    if (c.a.robot == c.b.robot && !linked(c.a.robot)) own_loops[c.a.robot].push_back(&c);
  }
  for (auto it = own_frames_.begin(); it != own_frames_.end();) {
    it = own_loops.count(it->first) ? std::next(it) : own_frames_.erase(it);  // linked meanwhile
  }
  for (const auto& [robot, list] : own_loops) {
    OwnFrame& frame = own_frames_[robot];
    if (frame.loops == list.size()) continue;  // newer keyframes: carried in refined_local_pose
    PoseGraph2d graph(options_.graph);
    const Keyframe* prev = nullptr;
    SE2 prev_initial;
    for (auto it = keyframes_.lower_bound(KeyframeId{robot, 0}); it != keyframes_.end() && it->first.robot == robot;
         ++it) {
      const Keyframe& kf = it->second;
      bool gap = false;
      const PoseGraphEdge edge = prev ? chain_edge(*prev, kf, &gap) : PoseGraphEdge{};
      auto solved = frame.poses.find(kf.id);  // warm start from the last solve
      const SE2 initial = solved != frame.poses.end() ? solved->second
                          : prev                      ? prev_initial * edge.T_from_to
                                                      : kf.T_local_base;
      graph.add_node(kf.id, initial);
      if (prev) {
        graph.add_edge(edge);
      } else {
        graph.set_prior(PosePrior{kf.id, kf.T_local_base});  // the gauge: the robot's own start
      }
      prev = &kf;
      prev_initial = initial;
    }
    for (const LoopClosure* c : list) {
      graph.add_edge(loop_edge(*c));
    }
    graph.solve(options_.solve);
    frame.poses = graph.estimates();
    frame.loops = list.size();
  }
}

SE2 MultiRobotMapper::refined_local_pose(KeyframeId id) const {
  const Keyframe& kf = keyframes_.at(id);
  if (linked(id.robot)) return correction(id.robot).inverse() * *global_pose(id);
  const auto frame = own_frames_.find(id.robot);
  if (frame == own_frames_.end()) return agent_local_pose(id);
  auto solved = frame->second.poses.upper_bound(id);  // the last solved keyframe at or before id
  if (solved == frame->second.poses.begin()) return agent_local_pose(id);
  --solved;
  return solved->second * keyframes_.at(solved->first).T_local_base.between(kf.T_local_base);
}

bool MultiRobotMapper::try_link_pair(RobotId ra, RobotId rb, std::vector<LoopClosure>* candidates,
                                     OptimizeResult* result) {
  const LocalPoseFn local_pose = [this](KeyframeId id) { return refined_local_pose(id); };
  const std::pair<RobotId, RobotId> key{ra, rb};
  while (true) {
    const std::vector<size_t> clique = pcm_max_clique(*candidates, local_pose, options_.pcm);
    if (int(clique.size()) < options_.min_link_clique) return false;
    std::vector<LoopClosure> members;
    for (size_t i : clique) members.push_back((*candidates)[i]);
    const std::string deficit = spread_deficit(members);
    if (!deficit.empty()) {  // maybe right, but too local to tell aliasing apart: wait
      if (last_verdict_[key] != deficit) {
        last_verdict_[key] = deficit;
        ++link_stats_.deferred_spread;
        result->link_events.push_back(LinkEvent{rb, ra, int(members.size()), false, false, 0.0, deficit, members});
      }
      return false;
    }
    LinkEvent ev = judge_link(ra, rb, members);
    ev.members = members;
    ev.robot = linked(ra) || !linked(rb) ? rb : ra;
    ev.other = ev.robot == rb ? ra : rb;
    if (ev.inconclusive) {  // not refuted, not confirmed: wait for more keyframes
      if (last_verdict_[key] != ev.reason) {
        last_verdict_[key] = ev.reason;
        ++link_stats_.deferred_inconclusive;
        result->link_events.push_back(ev);
      }
      return false;
    }
    ++link_stats_.hypotheses;
    last_verdict_[key] = ev.reason;
    result->link_events.push_back(ev);
    if (!ev.accepted) {  // refuted as a set: drop these closures, look at the rest
      ++link_stats_.rejected_map_contradiction;
      for (auto i = clique.rbegin(); i != clique.rend(); ++i) candidates->erase(candidates->begin() + long(*i));
      continue;
    }
    ++link_stats_.linked;
    // A member off the clique's common fit by more than a linked pair's gate (PCM's pairwise test
    // lets a 0.5 m / 4 deg closure join three right ones on the MIT CSAIL split) waits, held, for
    // the map check a closure into a linked pair gets once the robots are placed.
    // The member nearest the fit always enters: the robot is placed through accepted closures.
    const SE2 T_fit = link_hypothesis(ra, members);
    std::vector<double> misfit;
    for (const LoopClosure& c : members) misfit.push_back(link_misfit(ra, T_fit, c));
    const size_t nearest = size_t(std::min_element(misfit.begin(), misfit.end()) - misfit.begin());
    for (size_t i = 0; i < members.size(); ++i) {
      if (i == nearest || misfit[i] <= 1.0) {
        loops_.push_back(members[i]);
      } else {
        held_closures_.push_back(members[i]);
        ++link_stats_.link_members_held;
      }
    }
    // The guided search's closures tied the robot's map to the others' where they overlap when it
    // was judged: they join the graph with the clique.
    for (const LoopClosure& g : ev.guided) {  // a member on the same pair (even a held one) wins
      const bool member = std::any_of(members.begin(), members.end(), [&](const LoopClosure& c) {
        return (c.a == g.a && c.b == g.b) || (c.a == g.b && c.b == g.a);  // guided: a on the placed side
      });
      if (!member) loops_.push_back(g);
    }
    const RobotId ca = component_of(ra), cb = component_of(rb);
    // The anchor's component keeps its root.
    if (anchor_ && component_of(*anchor_) == cb) {
      component_parent_[ca] = cb;
    } else {
      component_parent_[cb] = ca;
    }
    result->newly_linked.push_back(ev.robot);
    full_resolve_ = true;
    return true;
  }
}

void MultiRobotMapper::place_new_robots() {
  if (!anchor_) return;
  // Breadth-first over accepted inter-robot closures from the linked robots.
  bool changed = true;
  while (changed) {
    changed = false;
    for (const LoopClosure& c : loops_) {
      if (c.a.robot == c.b.robot || linked(c.a.robot) == linked(c.b.robot)) continue;
      if (component_of(c.a.robot) != component_of(*anchor_) || component_of(c.b.robot) != component_of(*anchor_))
        continue;
      const Keyframe& ka = keyframes_.at(c.a);
      const Keyframe& kb = keyframes_.at(c.b);
      if (linked(c.a.robot)) {
        starts_[c.b.robot] = correction(c.a.robot) * ka.T_local_base * c.T_a_b * kb.T_local_base.inverse();
      } else {
        starts_[c.a.robot] = correction(c.b.robot) * kb.T_local_base * c.T_a_b.inverse() * ka.T_local_base.inverse();
      }
      changed = true;
      ++poses_version_;
    }
  }
}

void MultiRobotMapper::add_loop_edges() {
  loop_in_graph_.resize(loops_.size(), false);
  for (size_t i = 0; i < loops_.size(); ++i) {
    const LoopClosure& c = loops_[i];
    if (loop_in_graph_[i] || !graph_.has_node(c.a) || !graph_.has_node(c.b)) continue;
    loop_in_graph_[i] = graph_.add_edge(loop_edge(c));
  }
}

// update_graph() and optimize() live in multi_robot_mapper.cpp (the incremental solve).

}  // namespace cairn::base
