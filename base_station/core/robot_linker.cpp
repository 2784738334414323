// RobotLinker: the anchor, robot components, loop detection, unlinked robots' own frames, scan
// links of robot pairs and placing linked robots (see robot_linker.h).
#include "base_station/core/robot_linker.h"

#include "base_station/core/sightings.h"

#include <Eigen/Cholesky>
#include <algorithm>

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

RobotLinker::RobotLinker(const MapperOptions& options) : options_(options), loop_closer_(options.loop_closer) {}

bool RobotLinker::note_keyframe(const Keyframe& kf, MapperData* data) {
  detect_queue_.push_back(kf.id);
  const LandmarkOptions& o = options_.landmarks;
  if (o.enabled && !kf.landmarks.empty()) {
    landmark_observations_[kf.id.robot] +=
        accumulate_landmarks(kf, o.min_range_m, &data->local_landmarks[kf.id.robot], nullptr);
    const std::vector<Sighting> sightings = sightings_in(kf, nullptr);
    sighting_counts_[kf.id.robot] += int(sightings.size());
    data->sightings.insert(data->sightings.end(), sightings.begin(), sightings.end());
  }
  if (anchor_committed_ || !data->hints.empty() || (data->anchor && !(kf.id.robot < *data->anchor))) return false;
  if (data->anchor) data->starts.erase(*data->anchor);
  data->anchor = kf.id.robot;
  data->starts[kf.id.robot] = SE2();
  return true;
}

LinkUpdate RobotLinker::update(MapperData* data) {
  LinkUpdate update;
  choose_anchor(data);
  link_by_landmarks(data, &update);   // robot_linker_landmarks.cpp
  link_by_sightings(data, &update);   // robot_linker_landmarks.cpp
  judge_alignments(data, &update);    // robot_linker_operator.cpp
  search_entry_hints(data, &update);  // robot_linker_hints.cpp
  if (options_.detect_loops) {
    detect_new_loops(data, &update);
    refresh_own_frames(data);
    link_robot_pairs(data, &update);
  }
  place_new_robots(data, &update);
  release_held_closures(data, &update);
  return update;
}

void RobotLinker::choose_anchor(MapperData* data) {
  if (anchor_committed_ || data->keyframes.empty()) return;
  if (!data->hints.empty()) {
    data->anchor = data->hints.begin()->first;
  } else {
    data->anchor = data->keyframes.begin()->first.robot;  // lowest id seen
    data->starts[*data->anchor] = SE2();
  }
  anchor_committed_ = true;
}

RobotId RobotLinker::component_of(const MapperData& data, RobotId robot) const {
  // Hinted robots and the anchor share the anchor's component.
  if (data.anchor && (data.hints.count(robot) || robot == *data.anchor)) robot = *data.anchor;
  auto it = component_parent_.find(robot);
  while (it != component_parent_.end() && it->second != robot) {
    robot = it->second;
    it = component_parent_.find(robot);
  }
  return robot;
}

void RobotLinker::join_components(const MapperData& data, RobotId ra, RobotId rb) {
  const RobotId ca = component_of(data, ra), cb = component_of(data, rb);
  if (data.anchor && component_of(data, *data.anchor) == cb) {  // the anchor's component keeps its root
    component_parent_[ca] = cb;
  } else {
    component_parent_[cb] = ca;
  }
}

void RobotLinker::detect_new_loops(MapperData* data, LinkUpdate* update) {
  for (KeyframeId id : detect_queue_) {
    if (const std::optional<LoopClosure> c = start_closure(*data, id); c && accept_intra_robot_closure(*data, *c)) {
      data->loops.push_back(*c);
      ++stats_.start_closures;
    }
    for (const LoopClosure& c : loop_closer_.add_and_detect(data->keyframe(id), data->keyframes)) {
      if (c.a.robot == c.b.robot || component_of(*data, c.a.robot) == component_of(*data, c.b.robot)) {
        // Intra-robot: must agree with the robot's own poses up to its drift; a pair already
        // linked: a closure that would move a linked robot must pass the map check first.
        if (accept_linked_pair_closure(*data, c, update)) data->loops.push_back(c);
      } else if (const auto chi2 = hint_chi2(*data, c); chi2 && *chi2 > options_.entry_hint_chi2) {
        ++stats_.hint_refused;  // a look-alike place far from where the team says the robot entered
      } else {
        const auto key = std::minmax(c.a.robot, c.b.robot);
        // Orient every candidate of a pair the same way (a = lower robot id) for PCM.
        inter_candidates_[{key.first, key.second}].push_back(c.a.robot == key.first ? c : reversed(c));
      }
    }
  }
  detect_queue_.clear();
  for (const auto& [pair, list] : inter_candidates_) update->pending_candidates += int(list.size());
}

void RobotLinker::link_robot_pairs(MapperData* data, LinkUpdate* update) {
  for (auto it = inter_candidates_.begin(); it != inter_candidates_.end();) {
    const auto [ra, rb] = it->first;
    if (component_of(*data, ra) == component_of(*data, rb)) {  // linked through a third robot meanwhile
      for (const LoopClosure& c : it->second) {
        if (accept_linked_pair_closure(*data, c, update)) data->loops.push_back(c);
      }
      it = inter_candidates_.erase(it);
      continue;
    }
    if (try_link_pair(data, ra, rb, &it->second, update)) {
      it = inter_candidates_.erase(it);
    } else {
      ++it;
    }
  }
}

void RobotLinker::refresh_own_frames(MapperData* data) const {
  std::map<RobotId, std::vector<const LoopClosure*>> own_loops;
  for (const LoopClosure& c : data->loops) {
    if (c.a.robot == c.b.robot && !data->linked(c.a.robot)) own_loops[c.a.robot].push_back(&c);
  }
  for (auto it = data->own_frames.begin(); it != data->own_frames.end();) {
    it = own_loops.count(it->first) ? std::next(it) : data->own_frames.erase(it);  // linked meanwhile
  }
  for (const auto& [robot, list] : own_loops) {
    OwnFrame& frame = data->own_frames[robot];
    if (frame.loops == list.size()) continue;  // newer keyframes: carried in refined_local_pose
    KeyframePoseGraph graph(options_.graph);
    const Keyframe* prev = nullptr;
    SE2 prev_initial;
    for (const auto& [id, kf] : data->robot_keyframes(robot)) {
      bool gap = false;
      const PoseGraphEdge edge = prev ? chain_edge(*data, *prev, kf, options_, &gap) : PoseGraphEdge{};
      auto solved = frame.poses.find(id);  // warm start from the last solve
      const SE2 initial = solved != frame.poses.end() ? solved->second
                          : prev                      ? prev_initial * edge.T_from_to
                                                      : kf.T_local_base;
      graph.add_node(id, initial);
      if (prev) {
        graph.add_edge(edge);
      } else {
        graph.set_prior(PosePrior{id, kf.T_local_base});  // the gauge: the robot's own start
      }
      prev = &kf;
      prev_initial = initial;
    }
    for (const LoopClosure* c : list) graph.add_edge(loop_edge(*c));
    graph.solve(options_.solve);
    frame.poses = graph.estimates();
    frame.loops = list.size();
  }
}

bool RobotLinker::try_link_pair(MapperData* data, RobotId ra, RobotId rb, std::vector<LoopClosure>* candidates,
                                LinkUpdate* update) {
  const LocalPoseFn local_pose = [data](KeyframeId id) { return data->refined_local_pose(id); };
  const std::pair<RobotId, RobotId> key{ra, rb};
  while (true) {
    const std::vector<size_t> clique = pcm_max_clique(*candidates, local_pose, options_.pcm);
    if (int(clique.size()) < options_.min_link_clique) return false;
    std::vector<LoopClosure> members;
    for (size_t i : clique) members.push_back((*candidates)[i]);
    // A clique under tight hints that each of its closures confirms needs no spread: the hint
    // pins the link's rotation and rules out look-alike spots.
    std::string deficit = spread_deficit(*data, members);
    if (!deficit.empty() && hint_confirms(*data, members)) deficit.clear();
    if (!deficit.empty()) {  // maybe right, but too local to tell aliasing apart: wait
      if (last_verdict_[key] != deficit) {
        last_verdict_[key] = deficit;
        ++stats_.deferred_spread;
        update->events.push_back(LinkEvent{rb, ra, int(members.size()), false, false, 0.0, deficit, members});
      }
      return false;
    }
    LinkEvent ev = judge_link(*data, ra, rb, members);
    ev.members = members;
    ev.robot = data->linked(ra) || !data->linked(rb) ? rb : ra;
    ev.other = ev.robot == rb ? ra : rb;
    if (ev.inconclusive) {  // not refuted, not confirmed: wait for more keyframes
      if (last_verdict_[key] != ev.reason) {
        last_verdict_[key] = ev.reason;
        ++stats_.deferred_inconclusive;
        update->events.push_back(ev);
      }
      return false;
    }
    ++stats_.hypotheses;
    last_verdict_[key] = ev.reason;
    update->events.push_back(ev);
    if (!ev.accepted) {  // refuted as a set: drop these closures, look at the rest
      ++stats_.rejected_map_contradiction;
      for (auto i = clique.rbegin(); i != clique.rend(); ++i) candidates->erase(candidates->begin() + long(*i));
      continue;
    }
    ++stats_.linked;
    // A member off the clique's common fit by more than a linked pair's gate (PCM's pairwise test
    // lets a 0.5 m / 4 deg closure join three right ones on the MIT CSAIL split) waits, held, for
    // the map check a closure into a linked pair gets once the robots are placed.
    // The member nearest the fit always enters: the robot is placed through accepted closures.
    const SE2 T_fit = link_hypothesis(*data, ra, members);
    std::vector<double> misfit;
    for (const LoopClosure& c : members) misfit.push_back(link_misfit(*data, ra, T_fit, c));
    const size_t nearest = size_t(std::min_element(misfit.begin(), misfit.end()) - misfit.begin());
    for (size_t i = 0; i < members.size(); ++i) {
      if (i == nearest || misfit[i] <= 1.0) {
        data->loops.push_back(members[i]);
      } else {
        held_closures_.push_back(members[i]);
        ++stats_.link_members_held;
      }
    }
    // The guided search's closures tied the robot's map to the others' where they overlap when it
    // was judged: they join the graph with the clique.
    for (const LoopClosure& g : ev.guided) {  // a member on the same pair (even a held one) wins
      const bool member = std::any_of(members.begin(), members.end(), [&](const LoopClosure& c) {
        return (c.a == g.a && c.b == g.b) || (c.a == g.b && c.b == g.a);  // guided: a on the placed side
      });
      if (!member) data->loops.push_back(g);
    }
    join_components(*data, ra, rb);
    update->newly_linked.push_back(ev.robot);
    update->full_resolve = true;
    return true;
  }
}

void RobotLinker::place_new_robots(MapperData* data, LinkUpdate* update) const {
  if (!data->anchor) return;
  const RobotId anchor_component = component_of(*data, *data->anchor);
  // Breadth-first over accepted inter-robot closures from the linked robots.
  bool changed = true;
  while (changed) {
    changed = false;
    for (const LoopClosure& c : data->loops) {
      if (c.a.robot == c.b.robot || data->linked(c.a.robot) == data->linked(c.b.robot)) continue;
      if (component_of(*data, c.a.robot) != anchor_component || component_of(*data, c.b.robot) != anchor_component)
        continue;
      const Keyframe& ka = data->keyframe(c.a);
      const Keyframe& kb = data->keyframe(c.b);
      if (data->linked(c.a.robot)) {
        data->starts[c.b.robot] = data->correction(c.a.robot) * ka.T_local_base * c.T_a_b * kb.T_local_base.inverse();
      } else {
        data->starts[c.a.robot] =
            data->correction(c.b.robot) * kb.T_local_base * c.T_a_b.inverse() * ka.T_local_base.inverse();
      }
      changed = true;
      update->placements_changed = true;
    }
  }
}

void RobotLinker::release_held_closures(MapperData* data, LinkUpdate* update) {
  std::vector<LoopClosure> held;
  held.swap(held_closures_);
  for (const LoopClosure& c : held) {
    if (accept_linked_pair_closure(*data, c, update)) data->loops.push_back(c);  // re-held if still unplaced
  }
}

}  // namespace cairn::base
