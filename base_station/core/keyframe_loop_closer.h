#pragma once
// Place recognition and verification for the merger (DESIGN.md "Base station" 2): each keyframe's
// Scan Context (sent by the agent, or computed here from its scan and its robot's previous
// keyframes when absent) goes into a database; a query is compared by ring key (linear search, no
// pose prior) with every keyframe of other robots and with older keyframes of its own robot, the
// best few by full Scan Context distance are verified by scan matching against a local map of the
// candidate's neighbouring keyframes (loop_verifier.h). Output: verified closures with covariance.
#include <map>
#include <optional>
#include <vector>

#include "base_station/core/loop_verifier.h"
#include "base_station/core/pcm.h"
#include "common/keyframe.h"
#include "common/scan_context.h"

namespace cairn::base {

struct KeyframeLoopCloserOptions {
  /// Must equal the agents' (both use the defaults of ScanContextOptions); a received descriptor
  /// of another size is ignored and recomputed here.
  ScanContextOptions scan_context;
  int ring_key_candidates = 6;  ///< best ring-key matches given the full distance
  double max_descriptor_distance = 0.35;
  int max_verifications = 2;         ///< per query, best descriptor distances first
  int min_intra_seq_gap = 15;        ///< own-robot candidates at least this many keyframes back
  int local_map_half_keyframes = 4;  ///< candidate's local map: seq - n .. seq + n
  /// The query side of a verification: the query keyframe's scan and those of its predecessors
  /// seq - 1 .. seq - n in its frame (a narrow laser sees too little alone to tell places apart).
  /// MIT CSAIL split (180-deg laser): 10 (with a 10-keyframe local map) doubled the correctly
  /// verified inter-robot candidates (10 -> 19) and cut the wrong ones (89 -> 58) against 0 / 4,
  /// but made optimize() 3-4x slower and linked fewer robots in the 360-degree simulated worlds,
  /// so the defaults stay 0 / 4 (see tests/multirobot/multirobot_split_test.cpp).
  int query_submap_keyframes = 0;
  LoopVerifierOptions verifier{0.05, 0.08, 6, 4.0, 0.4};
};

/// One candidate of the last query, for diagnostics (how far each true place got).
struct LoopCandidate {
  KeyframeId candidate;
  double ring_key_distance2 = 0.0;
  double descriptor_distance = 1.0;  ///< 1 when not compared
  bool descriptor_passed = false;    ///< below max_descriptor_distance
  bool verification_tried = false;
  bool verified = false;
  SE2 T_candidate_query;  ///< when verified
};

struct KeyframeLoopCloserStats {
  int queries = 0;
  int descriptor_matches = 0;
  int verifications = 0;
  int accepted = 0;
};

class KeyframeLoopCloser {
 public:
  explicit KeyframeLoopCloser(const KeyframeLoopCloserOptions& options = {});

  /// Adds `kf` (already stored in `keyframes`) to the database and returns the verified closures
  /// with keyframes already in the database: a = the older candidate, b = kf.
  std::vector<LoopClosure> add_and_detect(const Keyframe& kf, const std::map<KeyframeId, Keyframe>& keyframes);
  /// Verifies one given pair around a pose guess (no place recognition): `query`'s scan against the
  /// local map of `candidate`, searched within `verifier`'s windows around T_candidate_query.
  /// The merger's guided search around a link hypothesis (RobotLinker::guided_closures).
  std::optional<LoopClosure> verify_guided(KeyframeId candidate, KeyframeId query, const SE2& T_candidate_query,
                                           const std::map<KeyframeId, Keyframe>& keyframes,
                                           const LoopVerifierOptions& verifier) const;
  const KeyframeLoopCloserStats& stats() const { return stats_; }
  const std::vector<float>* descriptor(KeyframeId id) const;
  /// The ring-key candidates of the last add_and_detect call, best ring key first.
  const std::vector<LoopCandidate>& last_candidates() const { return last_candidates_; }

 private:
  struct Entry {
    std::vector<float> descriptor, ring_key;
  };
  std::vector<float> descriptor_of(const Keyframe& kf, const std::map<KeyframeId, Keyframe>& keyframes) const;
  /// The query side of a verification (KeyframeLoopCloserOptions::query_submap_keyframes).
  std::vector<Eigen::Vector2f> query_points(const Keyframe& kf, const std::map<KeyframeId, Keyframe>& keyframes) const;
  std::vector<Eigen::Vector2f> local_map(KeyframeId center, const std::map<KeyframeId, Keyframe>& keyframes) const;

  KeyframeLoopCloserOptions options_;
  std::map<KeyframeId, Entry> database_;
  KeyframeLoopCloserStats stats_;
  std::vector<LoopCandidate> last_candidates_;
};

}  // namespace cairn::base
