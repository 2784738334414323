#include "tests/multirobot/loop_funnel.h"

#include <cmath>
#include <map>

namespace cairn::multirobot {

std::vector<FunnelRow> loop_funnel(const std::vector<RobotRun>& runs, const base::KeyframeLoopCloserOptions& options,
                                   double true_radius_m, int optimize_every) {
  auto ref = [&](KeyframeId id) { return runs.at(size_t(id.robot.value)).reference.at(size_t(id.seq)); };
  std::map<std::pair<int, int>, FunnelRow> rows;
  auto row = [&](RobotId x, RobotId y) -> FunnelRow& {
    FunnelRow& r = rows[std::minmax(x.value, y.value)];
    r.a = RobotId(std::min(x.value, y.value));
    r.b = RobotId(std::max(x.value, y.value));
    return r;
  };
  base::KeyframeLoopCloser closer(options);
  std::map<KeyframeId, Keyframe> keyframes;
  std::vector<KeyframeId> queue, done;
  auto detect = [&] {
    for (KeyframeId q : queue) {
      closer.add_and_detect(keyframes.at(q), keyframes);
      const SE2 Rq = ref(q);
      std::map<int, bool> has_true;  // other robot -> a true neighbour is in the database
      for (KeyframeId d : done) {
        if (d.robot != q.robot && (ref(d).translation() - Rq.translation()).norm() < true_radius_m)
          has_true[d.robot.value] = true;
      }
      std::map<int, int> stage;  // other robot -> furthest stage reached by a true candidate
      for (const base::LoopCandidate& c : closer.last_candidates()) {
        if (c.candidate.robot == q.robot) continue;
        const SE2 truth = ref(c.candidate).between(Rq);
        if (c.verified) {
          const SE2 e = truth.between(c.T_candidate_query);
          if (e.translation().norm() > 0.3 || std::abs(e.yaw()) > 5 * M_PI / 180)
            ++row(q.robot, c.candidate.robot).verified_wrong;
        }
        if (truth.translation().norm() >= true_radius_m) continue;
        int s = 1 + int(c.descriptor_passed) + int(c.verification_tried);
        if (c.verified) {
          const SE2 e = truth.between(c.T_candidate_query);
          if (e.translation().norm() <= 0.3 && std::abs(e.yaw()) <= 5 * M_PI / 180) s = 4;
        }
        int& best = stage[c.candidate.robot.value];
        best = std::max(best, s);
      }
      for (const auto& [other, yes] : has_true) {
        FunnelRow& r = row(q.robot, RobotId(other));
        ++r.queries_with_true;
        const int s = stage.count(other) ? stage[other] : 0;
        r.ring_key += s >= 1;
        r.descriptor += s >= 2;
        r.tried += s >= 3;
        r.verified_true += s >= 4;
      }
      done.push_back(q);
    }
    queue.clear();
  };
  size_t longest = 0;
  for (const RobotRun& r : runs) longest = std::max(longest, r.keyframes.size());
  int added = 0;
  for (size_t step = 0; step < longest; ++step) {
    for (const RobotRun& r : runs) {
      const size_t from = r.keyframes.size() * step / longest, to = r.keyframes.size() * (step + 1) / longest;
      for (size_t i = from; i < to; ++i) {
        keyframes.emplace(r.keyframes[i].id, r.keyframes[i]);
        queue.push_back(r.keyframes[i].id);
        if (++added % optimize_every == 0) detect();
      }
    }
  }
  detect();
  std::vector<FunnelRow> out;
  for (const auto& [key, r] : rows) out.push_back(r);
  return out;
}

std::string to_string(const FunnelRow& r) {
  return "robots " + std::to_string(r.a.value) + "-" + std::to_string(r.b.value) + ": queries with a true neighbour " +
         std::to_string(r.queries_with_true) + ", true among ring-key candidates " + std::to_string(r.ring_key) +
         ", below descriptor distance " + std::to_string(r.descriptor) + ", verification tried " +
         std::to_string(r.tried) + ", verified correct " + std::to_string(r.verified_true) +
         "; verified wrong closures " + std::to_string(r.verified_wrong);
}

}  // namespace cairn::multirobot
