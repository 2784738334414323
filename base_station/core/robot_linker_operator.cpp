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
  const std::string name = "robot " + std::to_string(v->robot.value);
  v->state = AlignmentState::kRefused;
  v->plausible = false;
  if (data->linked(v->robot)) {
    v->reason = name + " is already on the map";
    return;
  }
  const PlacementJudgement j =
      judge_placement(*data, v->robot, v->requested, options_.operator_alignment, "the alignment");
  v->reason = j.reason;
  v->plausible = j.plausible;
  if (!j.accepted) return;
  v->state = AlignmentState::kAccepted;
  v->placed = j.placed;
  v->closures = int(j.agreeing.size());
  link_placement(data, v->robot, j, update);
}

RobotLinker::PlacementJudgement RobotLinker::judge_placement(const MapperData& data, RobotId rb,
                                                             const SE2& T_global_local,
                                                             const OperatorAlignmentOptions& o,
                                                             const std::string& what) const {
  PlacementJudgement j;
  if (!data.anchor || data.robot_keyframes(*data.anchor).empty()) {
    j.reason = "nothing is on the global map yet";
    return j;
  }
  if (data.robot_keyframes(rb).empty()) {
    j.reason = "no keyframes from robot " + std::to_string(rb.value) + " yet";
    return j;
  }
  const RobotId ra = *data.anchor;  // frame A: the global frame
  const std::vector<LoopClosure> found = guided_closures(data, ra, rb, T_global_local, o.search);
  const std::string window = format_number("%.1f m", o.search.verifier.linear_window_m) + " / " +
                             format_number("%.0f deg", o.search.verifier.angular_window_rad * 180.0 / M_PI);
  if (int(found.size()) < o.min_closures) {
    j.reason = std::to_string(found.size()) + " verified scan matches within " + window + " of " + what + " (" +
               std::to_string(o.min_closures) + " needed): its map does not overlap the global map there";
    j.plausible = true;
    return j;
  }
  // The matches' rigid fit, then only the matches that agree with it (a look-alike spot is off).
  const SE2 fit = link_hypothesis(data, ra, found);
  for (const LoopClosure& c : found) {
    if (link_misfit(data, ra, fit, c) <= 1.0) j.agreeing.push_back(c);
  }
  if (int(j.agreeing.size()) < o.min_closures) {
    j.reason = "the " + std::to_string(found.size()) + " verified scan matches near " + what + " disagree (" +
               std::to_string(j.agreeing.size()) + " agree with their best fit, " + std::to_string(o.min_closures) +
               " needed)";
    return j;
  }
  const LinkEvent map = judge_link(data, ra, rb, j.agreeing);
  if (!map.accepted) {
    j.reason =
        std::string(map.inconclusive ? "the map check is inconclusive: " : "the map check refutes it: ") + map.reason;
    j.plausible = map.inconclusive;
    return j;
  }
  j.accepted = true;
  j.guided = map.guided;
  j.placed = link_hypothesis(data, ra, j.agreeing);
  j.reason = "placed by " + std::to_string(j.agreeing.size()) + " verified scan matches, " +
             format_offset(T_global_local, j.placed) + " from " + what + "; the map check agrees";
  return j;
}

void RobotLinker::link_placement(MapperData* data, RobotId rb, const PlacementJudgement& j, LinkUpdate* update) {
  const RobotId ra = *data->anchor;
  ++stats_.hypotheses;
  ++stats_.linked;
  data->loops.insert(data->loops.end(), j.agreeing.begin(), j.agreeing.end());
  for (const LoopClosure& g : j.guided) {  // the guided check's own matches, unless already in
    const bool in = std::any_of(j.agreeing.begin(), j.agreeing.end(),
                                [&](const LoopClosure& c) { return c.a == g.a && c.b == g.b; });
    if (!in) data->loops.push_back(g);
  }
  join_components(*data, ra, rb);
  update->newly_linked.push_back(rb);
  update->full_resolve = true;
}

}  // namespace cairn::base
