// RobotLinker: checks of link hypotheses before robots are merged (see robot_linker.h and
// map_consistency.h): the spread of a clique's closures over both trajectories, and the
// map-level consistency of the hypothesis over all keyframes seen so far.
#include <cmath>
#include <cstdio>

#include "base_station/core/robot_linker.h"
#include "common/trajectory.h"

namespace cairn::base {
namespace {

/// Largest distance between two of `points`.
double extent_m(const std::vector<Eigen::Vector2d>& points) {
  double best = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) best = std::max(best, (points[i] - points[j]).norm());
  }
  return best;
}

/// Mean of rigid transforms (translation mean, circular yaw mean).
SE2 mean_transform(const std::vector<SE2>& transforms) {
  Eigen::Vector2d t = Eigen::Vector2d::Zero();
  double s = 0, c = 0;
  for (const SE2& T : transforms) {
    t += T.translation();
    s += std::sin(T.yaw());
    c += std::cos(T.yaw());
  }
  return transforms.empty() ? SE2() : SE2(t / double(transforms.size()), std::atan2(s, c));
}

std::string format_m(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

/// Every linked robot's keyframes at T_frame_global * global pose.
PlacedScans linked_scans(const MapperData& data, const SE2& T_frame_global) {
  PlacedScans out;
  for (const auto& [id, kf] : data.keyframes) {
    if (!data.linked(id.robot)) continue;
    out.keyframes.push_back(&kf);
    out.T_frame_base.push_back(T_frame_global * *data.global_pose(id));
  }
  return out;
}

/// One robot's keyframes at T_frame_local * refined local pose.
PlacedScans robot_scans(const MapperData& data, RobotId robot, const SE2& T_frame_local) {
  PlacedScans out;
  for (const auto& [id, kf] : data.robot_keyframes(robot)) {
    out.keyframes.push_back(&kf);
    out.T_frame_base.push_back(T_frame_local * data.refined_local_pose(id));
  }
  return out;
}

}  // namespace

std::string RobotLinker::spread_deficit(const MapperData& data, const std::vector<LoopClosure>& closures) const {
  std::vector<Eigen::Vector2d> pa, pb;
  for (const LoopClosure& c : closures) {
    pa.push_back(data.refined_local_pose(c.a).translation());
    pb.push_back(data.refined_local_pose(c.b).translation());
  }
  const double ea = extent_m(pa), eb = extent_m(pb);
  if (ea >= options_.min_link_spread_m || eb >= options_.min_link_spread_m) return {};
  return "closures span " + format_m(ea) + " m / " + format_m(eb) + " m of the trajectories (< " +
         format_m(options_.min_link_spread_m) + " m on both): waiting for closures from other places";
}

SE2 RobotLinker::link_hypothesis(const MapperData& data, RobotId ra, const std::vector<LoopClosure>& closures) const {
  std::vector<SE2> T_A_blocal;
  // Both keyframes of each closure, in rb's local frame and in frame A.
  std::vector<Eigen::Vector2d> a_in_blocal, b_in_blocal, a_in_A, b_in_A;
  for (const LoopClosure& c : closures) {
    const SE2 T_A_a = data.pose_in_frame_a(ra, c.a);
    const SE2 T_blocal_b = data.refined_local_pose(c.b);
    T_A_blocal.push_back(T_A_a * c.T_a_b * T_blocal_b.inverse());
    b_in_blocal.push_back(T_blocal_b.translation());
    b_in_A.push_back((T_A_a * c.T_a_b).translation());
    a_in_blocal.push_back((T_blocal_b * c.T_a_b.inverse()).translation());
    a_in_A.push_back(T_A_a.translation());
  }
  // The rigid transform that best fits the closures' keyframe positions when either side's are
  // spread out (a few degrees of error in each closure's own yaw, 2-7 deg on the MIT CSAIL split,
  // swing a 30 m map by metres; the lever arm between closures pins the rotation far better),
  // else the mean of the closures' transforms.
  if (std::max(extent_m(a_in_blocal), extent_m(b_in_blocal)) < options_.min_link_spread_m)
    return mean_transform(T_A_blocal);
  b_in_blocal.insert(b_in_blocal.end(), a_in_blocal.begin(), a_in_blocal.end());
  b_in_A.insert(b_in_A.end(), a_in_A.begin(), a_in_A.end());
  return align_points_2d(b_in_blocal, b_in_A);
}

LinkEvent RobotLinker::judge_link(const MapperData& data, RobotId ra, RobotId rb,
                                  const std::vector<LoopClosure>& closures) const {
  LinkEvent ev{rb, ra, int(closures.size()), false, false, 0.0, {}};
  if (!options_.check_map_consistency) {
    ev.accepted = true;
    ev.reason = "linked (map check off)";
    return ev;
  }
  if (!data.linked(ra) && data.linked(rb)) {  // judge from the placed side
    std::vector<LoopClosure> flipped;
    for (const LoopClosure& c : closures) flipped.push_back(reversed(c));
    LinkEvent e = judge_link(data, rb, ra, flipped);
    return e;
  }
  // Frame A: the global frame when ra is placed, else ra's local frame.
  const SE2 T_hypothesis = link_hypothesis(data, ra, closures);
  const PlacedScans side_a = data.linked(ra) ? linked_scans(data, SE2()) : robot_scans(data, ra, SE2());
  const GuidedLinkOptions& guided = options_.guided_link;
  const bool guided_first = guided.enabled && guided.on_every_link;
  MapConsistencyResult m;
  if (!guided_first) m = check_map_consistency(side_a, robot_scans(data, rb, T_hypothesis), options_.map_check);
  const bool near_miss = !m.consistent && m.contradiction_ratio <= guided.max_rigid_contradiction_ratio;
  if (guided_first || (guided.enabled && near_miss)) {
    // Maybe the robots' own drift away from the clique: judged as the closures found around the
    // hypothesis place rb (MapperOptions::guided_link).
    ev.rigid_contradiction_ratio = guided_first ? -1.0 : m.contradiction_ratio;
    std::vector<LoopClosure> found = guided_closures(data, ra, rb, T_hypothesis);
    if (!found.empty()) {
      const MapConsistencyResult g = check_map_consistency(
          side_a, tentative_placement(data, ra, rb, T_hypothesis, closures, &found), options_.map_check);
      // A second chance only ever accepts; its refusal leaves the rigid verdict standing.
      if (guided_first || (g.consistent && g.conclusive)) {
        m = g;
        ev.guided = std::move(found);
      }
    } else if (guided_first) {
      m = check_map_consistency(side_a, robot_scans(data, rb, T_hypothesis), options_.map_check);
    }
  }
  ev.contradiction_ratio = m.contradiction_ratio;
  ev.accepted = m.consistent && m.conclusive;
  ev.inconclusive = m.consistent && !m.conclusive;
  ev.reason = ev.accepted ? "linked" : m.reason;
  return ev;
}

double RobotLinker::link_misfit(const MapperData& data, RobotId ra, const SE2& T_A_blocal, const LoopClosure& c) const {
  const SE2 T_A_a = data.pose_in_frame_a(ra, c.a);
  const SE2 E = (T_A_blocal * data.refined_local_pose(c.b)).between(T_A_a * c.T_a_b);
  return std::max(E.translation().norm() / options_.linked_closure_gate_m,
                  std::abs(E.yaw()) / options_.linked_closure_gate_rad);
}

std::optional<double> RobotLinker::hint_chi2(const MapperData& data, const LoopClosure& c) const {
  // Orient the closure so that b is the unplaced hinted robot.
  const auto hinted = [&](RobotId r) { return !data.linked(r) && data.entry_hints.count(r) > 0; };
  const LoopClosure l = hinted(c.b.robot) ? c : hinted(c.a.robot) ? reversed(c) : c;
  if (!hinted(l.b.robot)) return std::nullopt;
  const auto a = placed_or_hinted(data, l.a, /*tight_only=*/false);
  if (!a) return std::nullopt;  // nothing places the other side
  // The start of b this closure implies, against b's hint (error at b's entry), the other side's
  // hint variances added when that is what places it.
  return data.entry_hints.at(l.b.robot).chi2(a->T_global * l.T_a_b * data.refined_local_pose(l.b).inverse(),
                                             a->var_xy_m2, a->var_yaw_rad2);
}

std::optional<RobotLinker::HintedPose> RobotLinker::placed_or_hinted(const MapperData& data, KeyframeId id,
                                                                     bool tight_only) const {
  if (data.linked(id.robot)) return HintedPose{*data.global_pose(id)};
  const auto hint = data.entry_hints.find(id.robot);
  if (hint == data.entry_hints.end() || (tight_only && !is_tight(hint->second))) return std::nullopt;
  const EntryHint& h = hint->second;
  return HintedPose{h.T_global_local * data.refined_local_pose(id), h.sigma_xy_m * h.sigma_xy_m,
                    h.sigma_yaw_rad * h.sigma_yaw_rad};
}

bool RobotLinker::accept_intra_robot_closure(const MapperData& data, const LoopClosure& c) {
  ++stats_.intra_closures;
  // Path length between the two keyframes, over the stored ones (a gap counts its straight line).
  double path_m = 0.0;
  const Keyframe* prev = nullptr;
  for (auto it = data.keyframes.lower_bound(std::min(c.a, c.b));
       it != data.keyframes.end() && !(std::max(c.a, c.b) < it->first); ++it) {
    if (prev) path_m += prev->T_local_base.between(it->second.T_local_base).translation().norm();
    prev = &it->second;
  }
  const SE2 E = data.agent_local_pose(c.a).between(data.agent_local_pose(c.b)).between(c.T_a_b);
  if (E.translation().norm() <= options_.intra_closure_gate_m + options_.intra_closure_gate_m_per_m * path_m &&
      std::abs(E.yaw()) <= options_.intra_closure_gate_rad + options_.intra_closure_gate_rad_per_m * path_m) {
    return true;
  }
  ++stats_.intra_rejected;
  return false;
}

bool RobotLinker::accept_linked_pair_closure(const MapperData& data, const LoopClosure& c, LinkUpdate* update) {
  if (c.a.robot == c.b.robot) return accept_intra_robot_closure(data, c);
  if (!data.linked(c.a.robot) || !data.linked(c.b.robot)) {  // no placement to check against yet: hold it
    held_closures_.push_back(c);
    return false;
  }
  ++stats_.linked_pair_closures;
  const SE2 Ga = *data.global_pose(c.a), Gb = *data.global_pose(c.b);
  const SE2 E = Ga.between(Gb).between(c.T_a_b);
  if (E.translation().norm() <= options_.linked_closure_gate_m &&
      std::abs(E.yaw()) <= options_.linked_closure_gate_rad) {
    return true;
  }
  if (E.translation().norm() > options_.linked_closure_max_correction_m ||
      std::abs(E.yaw()) > options_.linked_closure_max_correction_rad) {
    ++stats_.linked_pair_implausible;
    char why[160];
    std::snprintf(why, sizeof(why), "disagrees with the linked estimate by %.1f m / %.0f deg, more than any drift",
                  E.translation().norm(), std::abs(E.yaw()) * 180.0 / M_PI);
    update->events.push_back(LinkEvent{c.b.robot, c.a.robot, 1, false, false, 0.0,
                                       "closure " + to_string(c.a) + " - " + to_string(c.b) + " rejected: " + why});
    return false;
  }
  if (!options_.check_map_consistency) return true;
  ++stats_.linked_pair_checked;
  // Hypothesis: robot b moves rigidly so that the closure holds. Compared near the closure only
  // (MapConsistencyOptions::local_radius_m): O(keyframes) to place them, not to render them.
  const SE2 T_moved_global = Ga * c.T_a_b * Gb.inverse();
  std::map<RobotId, SE2> corrections;  // global poses of keyframes not optimised yet
  for (const auto& [robot, start] : data.starts) corrections[robot] = data.correction(robot);
  PlacedScans others, moved;
  auto opt = data.optimized.begin();  // one merge pass: both maps are in id order
  for (const auto& [id, kf] : data.keyframes) {
    const auto corr = corrections.find(id.robot);
    if (corr == corrections.end()) continue;  // not linked
    while (opt != data.optimized.end() && opt->first < id) ++opt;
    const SE2 G = opt != data.optimized.end() && opt->first == id ? opt->second : corr->second * kf.T_local_base;
    PlacedScans& side = id.robot == c.b.robot ? moved : others;
    side.keyframes.push_back(&kf);
    side.T_frame_base.push_back(id.robot == c.b.robot ? T_moved_global * G : G);
  }
  if (options_.map_check.local_radius_m > 0) {
    const Eigen::Vector2d center_m = 0.5 * (Ga.translation() + (Ga * c.T_a_b).translation());
    others = select_near_keyframes(others, center_m, options_.map_check);
    moved = select_near_keyframes(moved, center_m, options_.map_check);
  }
  const MapConsistencyResult m = check_map_consistency(others, moved, options_.map_check);
  // A closure that would move a linked robot needs positive evidence: inconclusive is not enough.
  if (m.consistent && m.conclusive) return true;
  ++stats_.linked_pair_rejected;
  update->events.push_back(LinkEvent{c.b.robot, c.a.robot, 1, false, !m.conclusive, m.contradiction_ratio,
                                     "closure " + to_string(c.a) + " - " + to_string(c.b) + " rejected: " + m.reason});
  return false;
}

}  // namespace cairn::base
