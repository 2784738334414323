#include "base_station/core/keyframe_loop_closer.h"

#include <algorithm>

namespace cairn::base {
namespace {

/// Points of keyframe `other`'s scan expressed in keyframe `frame`'s base frame (local poses).
void append_points(const Keyframe& frame, const Keyframe& other, std::vector<Eigen::Vector2f>* out) {
  const SE2 T = frame.T_local_base.between(other.T_local_base);
  for (const Eigen::Vector2f& p : scan_to_points(other.scan)) out->push_back((T * p.cast<double>()).cast<float>());
}

}  // namespace

KeyframeLoopCloser::KeyframeLoopCloser(const KeyframeLoopCloserOptions& options) : options_(options) {}

const std::vector<float>* KeyframeLoopCloser::descriptor(KeyframeId id) const {
  auto it = database_.find(id);
  return it == database_.end() ? nullptr : &it->second.descriptor;
}

std::vector<float> KeyframeLoopCloser::descriptor_of(const Keyframe& kf,
                                                     const std::map<KeyframeId, Keyframe>& keyframes) const {
  if (scan_context_size_ok(kf.place_descriptor, options_.scan_context)) return kf.place_descriptor;
  std::vector<const Keyframe*> recent;
  for (int k = 1; k < options_.scan_context.descriptor_keyframes; ++k) {
    auto it = keyframes.find(KeyframeId{kf.id.robot, kf.id.seq - k});
    if (it != keyframes.end()) recent.push_back(&it->second);
  }
  return compute_keyframe_scan_context(kf, recent, options_.scan_context);
}

std::vector<Eigen::Vector2f> KeyframeLoopCloser::local_map(KeyframeId center,
                                                           const std::map<KeyframeId, Keyframe>& keyframes) const {
  std::vector<Eigen::Vector2f> points;
  const Keyframe& c = keyframes.at(center);
  const int n = options_.local_map_half_keyframes;
  for (auto it = keyframes.lower_bound(KeyframeId{center.robot, center.seq - n});
       it != keyframes.end() && it->first.robot == center.robot && it->first.seq <= center.seq + n; ++it) {
    append_points(c, it->second, &points);
  }
  return points;
}

std::vector<Eigen::Vector2f> KeyframeLoopCloser::query_points(const Keyframe& kf,
                                                              const std::map<KeyframeId, Keyframe>& keyframes) const {
  std::vector<Eigen::Vector2f> query = scan_to_points(kf.scan);
  for (int back = 1; back <= options_.query_submap_keyframes; ++back) {
    auto it = keyframes.find(KeyframeId{kf.id.robot, kf.id.seq - back});
    if (it != keyframes.end()) append_points(kf, it->second, &query);
  }
  return query;
}

std::optional<LoopClosure> KeyframeLoopCloser::verify_guided(KeyframeId candidate, KeyframeId query,
                                                             const SE2& T_candidate_query,
                                                             const std::map<KeyframeId, Keyframe>& keyframes,
                                                             const LoopVerifierOptions& verifier) const {
  const LoopVerification v = verify_loop(local_map(candidate, keyframes), query_points(keyframes.at(query), keyframes),
                                         T_candidate_query, verifier);
  if (!v.accepted) return std::nullopt;
  return LoopClosure{candidate, query, v.T_map_query, v.covariance, v.score};
}

std::vector<LoopClosure> KeyframeLoopCloser::add_and_detect(const Keyframe& kf,
                                                            const std::map<KeyframeId, Keyframe>& keyframes) {
  std::vector<LoopClosure> out;
  last_candidates_.clear();
  Entry entry;
  entry.descriptor = descriptor_of(kf, keyframes);
  entry.ring_key = scan_context_ring_key(entry.descriptor, options_.scan_context);
  if (entry.descriptor.empty()) return out;
  ++stats_.queries;
  // Ring-key pre-selection (rotation-invariant, no pose prior).
  std::vector<std::pair<double, KeyframeId>> near;
  for (const auto& [id, e] : database_) {
    if (id.robot == kf.id.robot && kf.id.seq - id.seq < options_.min_intra_seq_gap) continue;
    double d2 = 0;
    for (size_t r = 0; r < e.ring_key.size(); ++r)
      d2 += (e.ring_key[r] - entry.ring_key[r]) * (e.ring_key[r] - entry.ring_key[r]);
    near.push_back({d2, id});
  }
  const size_t k = std::min(near.size(), size_t(options_.ring_key_candidates));
  std::partial_sort(near.begin(), near.begin() + long(k), near.end());
  std::vector<std::pair<ScanContextMatch, size_t>> matches;  // second: index in last_candidates_
  for (size_t i = 0; i < k; ++i) {
    LoopCandidate cand{near[i].second, near[i].first};
    const ScanContextMatch m =
        scan_context_distance(database_.at(near[i].second).descriptor, entry.descriptor, options_.scan_context);
    if (m.valid) cand.descriptor_distance = m.distance;
    cand.descriptor_passed = m.valid && m.distance < options_.max_descriptor_distance;
    if (cand.descriptor_passed) matches.push_back({m, last_candidates_.size()});
    last_candidates_.push_back(cand);
  }
  std::sort(matches.begin(), matches.end(),
            [](const auto& a, const auto& b) { return a.first.distance < b.first.distance; });
  stats_.descriptor_matches += int(matches.size());
  const std::vector<Eigen::Vector2f> query = query_points(kf, keyframes);
  std::map<RobotId, LoopClosure> best_per_robot;
  for (size_t i = 0; i < matches.size() && int(i) < options_.max_verifications; ++i) {
    ++stats_.verifications;
    LoopCandidate& record = last_candidates_[matches[i].second];
    record.verification_tried = true;
    const KeyframeId cand = record.candidate;
    const LoopVerification v =
        verify_loop(local_map(cand, keyframes), query, SE2(0, 0, matches[i].first.yaw_rad), options_.verifier);
    if (!v.accepted) continue;
    record.verified = true;
    record.T_candidate_query = v.T_map_query;
    auto it = best_per_robot.find(cand.robot);
    if (it == best_per_robot.end() || it->second.score < v.score) {
      best_per_robot[cand.robot] = LoopClosure{cand, kf.id, v.T_map_query, v.covariance, v.score};
    }
  }
  for (const auto& [robot, c] : best_per_robot) out.push_back(c);
  stats_.accepted += int(out.size());
  database_.emplace(kf.id, std::move(entry));
  return out;
}

}  // namespace cairn::base
