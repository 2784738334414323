// MultiRobotMapper: the guided search around a link hypothesis (see multi_robot_mapper.h and
// MapperOptions::guided_link). A clique links a new robot at one place; elsewhere its map and the
// placed side's may be a few decimetres apart (each robot's own drift), and a rigid placement then
// puts one robot's walls in the other's corridor. When the rigid check does not accept it,
// keyframes of the new robot that the hypothesis puts near a keyframe of the placed side are
// scan-matched against it with a small search window; the new robot's keyframes are then solved
// against those closures (the placed side held fixed) and the check compares that placement. A
// wrong hypothesis is metres or tens of degrees off, which the small window cannot bridge, so it
// still meets the other map's walls.
#include <algorithm>
#include <cmath>

#include "base_station/core/multi_robot_mapper.h"

namespace cairn::base {
namespace {

double angle_between(double a_rad, double b_rad) { return std::abs(std::remainder(a_rad - b_rad, 2.0 * M_PI)); }

}  // namespace

std::vector<std::pair<KeyframeId, SE2>> MultiRobotMapper::placed_side(RobotId ra) const {
  std::vector<std::pair<KeyframeId, SE2>> out;
  for (const auto& [id, kf] : keyframes_) {
    if (linked(ra) ? linked(id.robot) : id.robot == ra) {
      out.push_back({id, linked(ra) ? *global_pose(id) : refined_local_pose(id)});
    }
  }
  return out;
}

std::vector<LoopClosure> MultiRobotMapper::guided_closures(RobotId ra, RobotId rb, const SE2& T_A_blocal) const {
  const GuidedLinkOptions& o = options_.guided_link;
  std::vector<LoopClosure> out;
  if (!o.enabled) return out;
  const std::vector<std::pair<KeyframeId, SE2>> side_a = placed_side(ra);
  // One query per sample_spacing_m of rb's path, at most max_verifications spread evenly.
  std::vector<std::pair<KeyframeId, SE2>> queries;  // rb keyframe, its hypothesised pose in frame A
  std::optional<Eigen::Vector2d> last;
  for (auto it = keyframes_.lower_bound(KeyframeId{rb, 0}); it != keyframes_.end() && it->first.robot == rb; ++it) {
    const SE2 T_local = refined_local_pose(it->first);
    if (last && (T_local.translation() - *last).norm() < o.sample_spacing_m) continue;
    last = T_local.translation();
    queries.push_back({it->first, T_A_blocal * T_local});
  }
  const size_t stride = queries.size() > size_t(o.max_verifications) ? (queries.size() + o.max_verifications - 1) / o.max_verifications : 1;
  for (size_t q = 0; q < queries.size(); q += stride) {
    const auto& [kb, T_A_b] = queries[q];
    const std::pair<KeyframeId, SE2>* nearest = nullptr;
    double best_m = o.max_distance_m;
    for (const auto& entry : side_a) {
      const double d = (entry.second.translation() - T_A_b.translation()).norm();
      if (d <= best_m && angle_between(entry.second.yaw(), T_A_b.yaw()) <= o.max_yaw_difference_rad) {
        best_m = d;
        nearest = &entry;
      }
    }
    if (!nearest) continue;
    const std::optional<LoopClosure> c =
        loop_closer_.verify_guided(nearest->first, kb, nearest->second.between(T_A_b), keyframes_, o.verifier);
    if (c) out.push_back(*c);
  }
  return out;
}

PlacedScans MultiRobotMapper::tentative_placement(RobotId ra, RobotId rb, const SE2& T_A_blocal,
                                                  const std::vector<LoopClosure>& clique,
                                                  std::vector<LoopClosure>* guided) const {
  const auto pose_A = [&](KeyframeId id) { return linked(ra) ? *global_pose(id) : refined_local_pose(id); };
  const auto solve = [&](const std::vector<LoopClosure>& ties) {
    PoseGraph2d graph(options_.graph);
    std::vector<KeyframeId> moving;
    const Keyframe* prev = nullptr;
    for (auto it = keyframes_.lower_bound(KeyframeId{rb, 0}); it != keyframes_.end() && it->first.robot == rb; ++it) {
      const Keyframe& kf = it->second;
      graph.add_node(kf.id, T_A_blocal * refined_local_pose(kf.id));
      moving.push_back(kf.id);
      if (prev) {  // the robot's own map as the base refined it, with its front end's uncertainty
        bool gap = false;
        PoseGraphEdge edge = chain_edge(*prev, kf, &gap);
        edge.T_from_to = refined_local_pose(prev->id).between(refined_local_pose(kf.id));
        graph.add_edge(edge);
      }
      prev = &kf;
    }
    for (const LoopClosure& c : ties) {  // a on the placed side, held where it is
      if (!graph.has_node(c.a)) graph.add_node(c.a, pose_A(c.a));
      graph.add_edge(loop_edge(c));
    }
    PoseGraphSolveOptions options = options_.solve;
    options.active_nodes = moving;
    graph.solve(options);
    return graph.estimates();
  };
  std::vector<LoopClosure> ties = clique;
  ties.insert(ties.end(), guided->begin(), guided->end());
  std::map<KeyframeId, SE2> solved = solve(ties);
  const size_t before = guided->size();
  const GuidedLinkOptions& o = options_.guided_link;
  guided->erase(std::remove_if(guided->begin(), guided->end(),
                               [&](const LoopClosure& c) {
                                 const SE2 E = pose_A(c.a).between(solved.at(c.b)).between(c.T_a_b);
                                 return E.translation().norm() > o.max_residual_m || std::abs(E.yaw()) > o.max_residual_rad;
                               }),
                guided->end());
  if (guided->size() != before) {
    ties = clique;
    ties.insert(ties.end(), guided->begin(), guided->end());
    solved = solve(ties);
  }
  PlacedScans out;
  for (auto it = keyframes_.lower_bound(KeyframeId{rb, 0}); it != keyframes_.end() && it->first.robot == rb; ++it) {
    out.keyframes.push_back(&it->second);
    out.T_frame_base.push_back(solved.at(it->first));
  }
  return out;
}

}  // namespace cairn::base
