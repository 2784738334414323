// RobotLinker: the search around entry hints (see MapperOptions::entry_hint_search). Scan Context
// recognises a place only from nearly the same spot, so robots that enter far apart are linked by
// it only once one drives where the other drove. A tight hint already says where a robot's map lies
// to within a metre or two; around it, verified scan matches between keyframes up to 6 m apart
// place the robot as soon as the two maps share a few walls. The hint is only where to look: the
// placement comes from the matches, must agree with the hint (the chi-square gate every closure
// under a hint passes) and must pass the map check, like every other link.
#include <cmath>

#include "base_station/core/robot_linker.h"

namespace cairn::base {

bool RobotLinker::is_tight(const EntryHint& hint) const {
  return hint.sigma_xy_m <= options_.tight_hint_max_sigma_xy_m &&
         hint.sigma_yaw_rad <= options_.tight_hint_max_sigma_yaw_rad + 1e-9;
}

bool RobotLinker::hint_confirms(const MapperData& data, const std::vector<LoopClosure>& clique) const {
  for (const LoopClosure& c : clique) {
    const auto a = placed_or_hinted(data, c.a, /*tight_only=*/true);
    const auto b = placed_or_hinted(data, c.b, /*tight_only=*/true);
    if (!a || !b || (a->var_xy_m2 == 0.0 && b->var_xy_m2 == 0.0)) return false;
    // Searched within one sigma of where the hints put b: a look-alike spot a metre off the truth
    // lies outside, the true one (the hint off by up to a sigma) inside.
    LoopVerifierOptions verifier = options_.entry_hint_search.search.search.verifier;
    verifier.linear_window_m = std::sqrt(a->var_xy_m2 + b->var_xy_m2);
    verifier.angular_window_rad = std::sqrt(a->var_yaw_rad2 + b->var_yaw_rad2);
    const auto found = loop_closer_.verify_guided(c.a, c.b, a->T_global.between(b->T_global), data.keyframes, verifier);
    if (!found) return false;
    const SE2 E = found->T_a_b.between(c.T_a_b);
    if (E.translation().norm() > options_.linked_closure_gate_m || std::abs(E.yaw()) > options_.linked_closure_gate_rad)
      return false;
  }
  return true;
}

void RobotLinker::search_entry_hints(MapperData* data, LinkUpdate* update) {
  const EntryHintSearchOptions& o = options_.entry_hint_search;
  if (!o.enabled || !data->anchor) return;
  for (const auto& [robot, hint] : data->entry_hints) {
    if (data->linked(robot) || robot == *data->anchor) continue;
    if (!is_tight(hint)) continue;  // a loose hint only narrows Scan Context's candidates (entry_hint_chi2)
    const auto searched = hint_searched_at_.find(robot);
    if (searched != hint_searched_at_.end() &&
        data->keyframes.size() < searched->second + size_t(std::max(o.retry_after_keyframes, 1)))
      continue;
    hint_searched_at_[robot] = data->keyframes.size();
    // Windows of 3 sigma in position and 2 in heading, the position's widened along the robot's
    // path by the heading's lever arm.
    OperatorAlignmentOptions search = o.search;
    search.search.verifier.linear_window_m = 3.0 * hint.sigma_xy_m;
    search.search.verifier.angular_window_rad = 2.0 * hint.sigma_yaw_rad;
    search.search.linear_window_m_per_m = 2.0 * hint.sigma_yaw_rad;
    PlacementJudgement j = judge_placement(*data, robot, hint.T_global_local, search, "its entry hint");
    if (j.accepted) {
      const double chi2 = hint.chi2(j.placed);
      if (chi2 > options_.entry_hint_chi2) {
        j.accepted = false;
        j.reason = "placed " + format_offset(hint.T_global_local, j.placed) + " off its entry hint (chi-square " +
                   format_number("%.1f", chi2) + " > " + format_number("%.2f", options_.entry_hint_chi2) + ")";
      }
    }
    if (j.accepted) link_placement(data, robot, j, update);
    // Refusals for want of overlap repeat on every search until the maps meet: not reported; the
    // others once each.
    std::string& said = hint_verdicts_[robot];
    if (j.accepted || (!j.plausible && said != j.reason)) {
      update->events.push_back(
          LinkEvent{robot, *data->anchor, int(j.agreeing.size()), j.accepted, false, 0.0, j.reason});
    }
    said = j.reason;
  }
}

}  // namespace cairn::base
