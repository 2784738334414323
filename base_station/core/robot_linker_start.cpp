// Closures from each robot's first keyframe to its keyframes soon after (StartClosureOptions).
#include "base_station/core/robot_linker.h"

namespace cairn::base {

std::optional<LoopClosure> RobotLinker::start_closure(const MapperData& data, KeyframeId id) const {
  const StartClosureOptions& o = options_.start_closures;
  if (o.every_keyframes <= 0) return std::nullopt;
  const RobotKeyframes own = data.robot_keyframes(id.robot);
  if (own.empty()) return std::nullopt;
  const KeyframeId first = own.begin()->first;
  const int after = id.seq - first.seq;
  if (after <= 0 || after > o.max_keyframes || after % o.every_keyframes != 0) return std::nullopt;
  const SE2 T_id_first = data.agent_local_pose(id).between(data.agent_local_pose(first));
  if (T_id_first.translation().norm() > o.max_distance_m) return std::nullopt;
  // The first keyframe's scan alone is the query: the local map of its neighbours would carry the
  // very edges this closure is to check. `id`'s local map (its neighbours before it) is the map.
  return loop_closer_.verify_guided(id, first, T_id_first, data.keyframes, o.verifier);
}

}  // namespace cairn::base
