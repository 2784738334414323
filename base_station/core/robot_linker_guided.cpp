// RobotLinker: the guided search around a link hypothesis (see robot_linker.h and
// MapperOptions::guided_link). A clique links a new robot at one place; elsewhere its map and the
// placed side's may be a few decimetres apart (each robot's own drift), and a rigid placement then
// puts one robot's walls in the other's corridor. When the rigid check refutes it by a near miss,
// keyframes of the new robot that the hypothesis puts near a keyframe of the placed side are
// scan-matched against it with a small search window; the new robot's keyframes are then solved
// against those closures (the placed side held fixed) and the check compares that placement. A
// wrong hypothesis is metres or tens of degrees off, which the small window cannot bridge, so it
// still meets the other map's walls.
#include <algorithm>
#include <cmath>

#include "base_station/core/robot_linker.h"

namespace cairn::base {
namespace {

double angle_between(double a_rad, double b_rad) { return std::abs(std::remainder(a_rad - b_rad, 2.0 * M_PI)); }

/// Frame A's keyframes with their poses there: every linked robot's (global) when ra is linked,
/// else ra's own (refined local poses).
std::vector<std::pair<KeyframeId, SE2>> placed_side(const MapperData& data, RobotId ra) {
  std::vector<std::pair<KeyframeId, SE2>> out;
  for (const auto& [id, kf] : data.keyframes) {
    if (data.linked(ra) ? data.linked(id.robot) : id.robot == ra) out.push_back({id, data.pose_in_frame_a(ra, id)});
  }
  return out;
}

}  // namespace

std::vector<LoopClosure> RobotLinker::guided_closures(const MapperData& data, RobotId ra, RobotId rb,
                                                      const SE2& T_A_blocal) const {
  return guided_closures(data, ra, rb, T_A_blocal, options_.guided_link);
}

std::vector<LoopClosure> RobotLinker::guided_closures(const MapperData& data, RobotId ra, RobotId rb,
                                                      const SE2& T_A_blocal, const GuidedLinkOptions& o) const {
  std::vector<LoopClosure> out;
  if (!o.enabled || o.max_verifications <= 0) return out;
  const std::vector<std::pair<KeyframeId, SE2>> side_a = placed_side(data, ra);
  // Queries: one of rb's keyframes per sample_spacing_m of its path whose hypothesised pose in
  // frame A has a placed keyframe near it, heading the same way (the nearest is matched).
  struct Query {
    KeyframeId kb;
    SE2 T_A_b;
    const std::pair<KeyframeId, SE2>* nearest;
  };
  std::vector<Query> queries;
  std::optional<Eigen::Vector2d> last;
  for (const auto& [id, kf] : data.robot_keyframes(rb)) {
    const SE2 T_local = data.refined_local_pose(id);
    if (last && (T_local.translation() - *last).norm() < o.sample_spacing_m) continue;
    last = T_local.translation();
    const SE2 T_A_b = T_A_blocal * T_local;
    const std::pair<KeyframeId, SE2>* nearest = nullptr;
    double best_m = o.max_distance_m;
    for (const auto& entry : side_a) {
      const double d = (entry.second.translation() - T_A_b.translation()).norm();
      if (d <= best_m && angle_between(entry.second.yaw(), T_A_b.yaw()) <= o.max_yaw_difference_rad) {
        best_m = d;
        nearest = &entry;
      }
    }
    if (nearest) queries.push_back({id, T_A_b, nearest});
  }
  // At most max_verifications, spread evenly along the path.
  const size_t budget = size_t(o.max_verifications);
  const size_t stride = (queries.size() + budget - 1) / budget;
  for (size_t q = 0; q < queries.size(); q += std::max<size_t>(stride, 1)) {
    const Query& query = queries[q];
    LoopVerifierOptions verifier = o.verifier;
    const double from_start_m = data.refined_local_pose(query.kb).translation().norm();
    verifier.linear_window_m =
        std::max(verifier.linear_window_m,
                 std::min(o.max_linear_window_m, verifier.linear_window_m + o.linear_window_m_per_m * from_start_m));
    const std::optional<LoopClosure> c = loop_closer_.verify_guided(
        query.nearest->first, query.kb, query.nearest->second.between(query.T_A_b), data.keyframes, verifier);
    if (c) out.push_back(*c);
  }
  return out;
}

PlacedScans RobotLinker::tentative_placement(const MapperData& data, RobotId ra, RobotId rb, const SE2& T_A_blocal,
                                             const std::vector<LoopClosure>& clique,
                                             std::vector<LoopClosure>* guided) const {
  const auto solve = [&](const std::vector<LoopClosure>& ties) {
    KeyframePoseGraph graph(options_.graph);
    std::vector<KeyframeId> moving;
    const Keyframe* prev = nullptr;
    for (const auto& [id, kf] : data.robot_keyframes(rb)) {
      graph.add_node(id, T_A_blocal * data.refined_local_pose(id));
      moving.push_back(kf.id);
      if (prev) {  // the robot's own map as the base refined it, with its front end's uncertainty
        bool gap = false;
        PoseGraphEdge edge = chain_edge(data, *prev, kf, options_, &gap);
        edge.T_from_to = data.refined_local_pose(prev->id).between(data.refined_local_pose(kf.id));
        graph.add_edge(edge);
      }
      prev = &kf;
    }
    for (const LoopClosure& c : ties) {  // a on the placed side, held where it is
      if (!graph.has_node(c.a)) graph.add_node(c.a, data.pose_in_frame_a(ra, c.a));
      graph.add_edge(loop_edge(c));
    }
    // The gauge: a placed node (constant anyway). Without a prior KeyframePoseGraph would hold the
    // lowest id constant, rb's first keyframe when rb's id is the lower one.
    if (!ties.empty()) graph.set_prior(PosePrior{ties.front().a, data.pose_in_frame_a(ra, ties.front().a)});
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
                                 const SE2 E = data.pose_in_frame_a(ra, c.a).between(solved.at(c.b)).between(c.T_a_b);
                                 return E.translation().norm() > o.max_residual_m ||
                                        std::abs(E.yaw()) > o.max_residual_rad;
                               }),
                guided->end());
  if (guided->size() != before) {
    ties = clique;
    ties.insert(ties.end(), guided->begin(), guided->end());
    solved = solve(ties);
  }
  PlacedScans out;
  for (const auto& [id, kf] : data.robot_keyframes(rb)) {
    out.keyframes.push_back(&kf);
    out.T_frame_base.push_back(solved.at(id));
  }
  return out;
}

}  // namespace cairn::base
