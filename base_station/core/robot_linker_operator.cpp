// RobotLinker: the operator's alignment of an unlinked robot (see robot_linker.h). In the console
// the operator drags and turns a robot's own map over the global map; that placement is a
// hypothesis, never a link by itself. Around it the guided search looks for verified scan matches
// between the robot's keyframes and the placed keyframes near them, with windows for a hand's error
// (MapperOptions::operator_alignment: 1.5 m, 20 deg) instead of a robot's drift; the matches' rigid
// fit refines the placement, matches off that fit are dropped, and the map check judges the refined
// placement exactly as it judges scan and marker links. A placement onto a look-alike wing finds
// matches (the rooms look alike) but the map check refutes it: the verdict says so, and why.
#include <algorithm>
#include <cmath>

#include "base_station/core/landmarks.h"
#include "base_station/core/robot_linker.h"

namespace cairn::base {

const char* to_string(AlignmentState state) {
  switch (state) {
    case AlignmentState::kPending:
      return "pending";
    case AlignmentState::kAccepted:
      return "accepted";
    case AlignmentState::kRefused:
      return "refused";
  }
  return "?";
}

void RobotLinker::request_alignment(RobotId robot, const SE2& T_global_local) {
  AlignmentVerdict& v = alignments_[robot];
  v = AlignmentVerdict{};
  v.robot = robot;
  v.requested = T_global_local;
}

void RobotLinker::judge_alignments(MapperData* data, LinkUpdate* update) {
  for (auto& [robot, verdict] : alignments_) {
    if (verdict.state == AlignmentState::kPending) judge_alignment(data, &verdict, update);
  }
}

void RobotLinker::judge_alignment(MapperData* data, AlignmentVerdict* v, LinkUpdate* update) {
  const OperatorAlignmentOptions& o = options_.operator_alignment;
  const RobotId rb = v->robot;
  const std::string name = "robot " + std::to_string(rb.value);
  v->state = AlignmentState::kRefused;
  v->plausible = false;
  if (!data->anchor || data->robot_keyframes(*data->anchor).empty()) {
    v->reason = "nothing is on the global map yet";
    return;
  }
  if (data->linked(rb)) {
    v->reason = name + " is already on the map";
    return;
  }
  if (data->robot_keyframes(rb).empty()) {
    v->reason = "no keyframes from " + name + " yet";
    return;
  }
  const RobotId ra = *data->anchor;  // frame A: the global frame
  const std::vector<LoopClosure> found = guided_closures(*data, ra, rb, v->requested, o.search);
  const std::string window = format_number("%.1f m", o.search.verifier.linear_window_m) + " / " +
                             format_number("%.0f deg", o.search.verifier.angular_window_rad * 180.0 / M_PI);
  if (int(found.size()) < o.min_closures) {
    v->reason = std::to_string(found.size()) + " verified scan matches within " + window + " of the alignment (" +
                std::to_string(o.min_closures) + " needed): its map does not overlap the global map there";
    v->plausible = true;
    return;
  }
  // The matches' rigid fit, then only the matches that agree with it (a look-alike spot is off).
  const SE2 fit = link_hypothesis(*data, ra, found);
  std::vector<LoopClosure> agreeing;
  for (const LoopClosure& c : found) {
    if (link_misfit(*data, ra, fit, c) <= 1.0) agreeing.push_back(c);
  }
  if (int(agreeing.size()) < o.min_closures) {
    v->reason = "the " + std::to_string(found.size()) + " verified scan matches near the alignment disagree (" +
                std::to_string(agreeing.size()) + " agree with their best fit, " + std::to_string(o.min_closures) +
                " needed)";
    return;
  }
  const LinkEvent map = judge_link(*data, ra, rb, agreeing);
  if (!map.accepted) {
    v->reason =
        std::string(map.inconclusive ? "the map check is inconclusive: " : "the map check refutes it: ") + map.reason;
    v->plausible = map.inconclusive;
    return;
  }
  const SE2 placed = link_hypothesis(*data, ra, agreeing);
  const SE2 moved = v->requested.between(placed);
  v->state = AlignmentState::kAccepted;
  v->placed = placed;
  v->closures = int(agreeing.size());
  v->reason = "placed by " + std::to_string(agreeing.size()) + " verified scan matches, " +
              format_number("%.2f m", (placed.translation() - v->requested.translation()).norm()) + " and " +
              format_number("%.1f deg", std::abs(moved.yaw()) * 180.0 / M_PI) +
              " from the alignment; the map check agrees";
  ++stats_.hypotheses;
  ++stats_.linked;
  data->loops.insert(data->loops.end(), agreeing.begin(), agreeing.end());
  for (const LoopClosure& g : map.guided) {  // the guided check's own matches, unless already in
    const bool in =
        std::any_of(agreeing.begin(), agreeing.end(), [&](const LoopClosure& c) { return c.a == g.a && c.b == g.b; });
    if (!in) data->loops.push_back(g);
  }
  join_components(*data, ra, rb);
  update->newly_linked.push_back(rb);
  update->full_resolve = true;
}

}  // namespace cairn::base
