#pragma once
// RobotLinker: every decision about which robots are placed relative to which (DESIGN.md "Base
// station" 2-3; in Cartographer's split, the constraint builder's part). Robots start at unknown
// relative poses. The first robot seen (the lowest id before the first update) anchors the global
// frame, unless set_robot_start hints exist. Other robots get linked by
// - verified inter-robot loop closures: Scan Context candidates, scan-matching verification
//   (KeyframeLoopCloser), then PCM (maximum clique) over each robot pair's closures before the pair
//   is first linked, the clique's spread over both trajectories, and a map-level consistency check
//   of the placement it implies (a wrong merge is worse than a late one);
// - shared identified landmarks (markers), aligned and put through the same map check;
// - robots seeing robots (sightings.h), aligned and judged as markers are;
// - the operator's alignment in the console: verified scan matches around it, then the map check.
// Once a pair is linked, a closure that would move it passes a gate and the map check first, and a
// closure within one robot must agree with its own map up to its drift. Each robot's first scan is
// also verified in the local maps of its keyframes soon after (start closures), which measures the
// heading its local SLAM loses while turning at its start.
// add-side calls only store (note_keyframe); every decision happens in update(), which returns
// what changed. Reads and writes MapperData (starts, loops, own frames), never the pose graph.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base_station/core/keyframe_loop_closer.h"
#include "base_station/core/map_consistency.h"
#include "base_station/core/mapper_data.h"
#include "base_station/core/mapper_options.h"

namespace cairn::base {

/// One decision on a link hypothesis (a PCM clique or shared markers between two robots, or a
/// closure that would move a linked pair), for the app's log: "robot 1 linked to robot 0 via 4
/// closures" or the reason.
struct LinkEvent {
  RobotId robot;  ///< the robot being linked (or whose closure was judged)
  RobotId other;
  int closures = 0;  ///< closures of the hypothesis
  bool accepted = false;
  bool inconclusive = false;         ///< too little overlap to judge: candidates kept, judged again later
  double contradiction_ratio = 0.0;  ///< map check (0 when not run)
  std::string reason;                ///< why rejected / deferred, or "linked"
  std::vector<LoopClosure> members;  ///< the judged closures (a link hypothesis' clique)
  /// Closures found around the hypothesis by the guided search (MapperOptions::guided_link), a on
  /// the placed side, when the link was accepted as they place the robot (empty otherwise).
  std::vector<LoopClosure> guided;
  /// The map check of the rigid placement when the guided search then ran (-1: it did not run).
  double rigid_contradiction_ratio = -1.0;
};

/// Counters of link decisions since construction.
struct LinkStats {
  int hypotheses = 0;  ///< cliques of at least min_link_clique judged
  int linked = 0;
  int rejected_map_contradiction = 0;  ///< cliques refuted by the map check (closures dropped)
  int deferred_spread = 0;             ///< cliques whose closures cover too little of a trajectory
  int deferred_inconclusive = 0;       ///< cliques whose maps overlap too little to be checked
  int link_members_held = 0;           ///< members of accepted cliques off their common fit: held for the map check
  int linked_pair_closures = 0;        ///< inter-robot closures into already linked pairs
  int linked_pair_implausible = 0;     ///< of those, disagreeing beyond any drift: dropped unchecked
  int linked_pair_checked = 0;         ///< of those, disagreeing with the estimate: map-checked
  int linked_pair_rejected = 0;        ///< of those, refuted and dropped
  int intra_closures = 0;              ///< verified closures within one robot's trajectory
  int intra_rejected = 0;              ///< of those, contradicting the robot's own map beyond its drift
  int start_closures = 0;              ///< of those, from a robot's first keyframe (StartClosureOptions)
  int hint_refused = 0;                ///< inter-robot closures off an entry hint (MapperOptions::entry_hint_chi2)
};

/// What one RobotLinker::update() changed.
struct LinkUpdate {
  /// Robots linked by scan closures (marker links are in RobotLinker::landmark_link_events()).
  std::vector<RobotId> newly_linked;
  std::vector<LinkEvent> events;    ///< decisions of this update (deduplicated per pair)
  bool full_resolve = false;        ///< a new link: re-initialise (LAGO) and solve the whole graph
  bool placements_changed = false;  ///< a robot's start was set: any global pose may have moved
  int pending_candidates = 0;       ///< verified inter-robot closures waiting for PCM
};

/// The operator's alignment of an unlinked robot's map over the global map (the console), and what
/// the base made of it (robot_linker_operator.cpp).
enum class AlignmentState { kPending, kAccepted, kRefused };
const char* to_string(AlignmentState state);
struct AlignmentVerdict {
  RobotId robot;
  SE2 requested;  ///< T_global_local as the operator placed it
  AlignmentState state = AlignmentState::kPending;
  SE2 placed;          ///< accepted: T_global_local the verified matches gave
  int closures = 0;    ///< verified scan matches that agreed
  std::string reason;  ///< why refused, or how it was placed
  /// Refused only for want of evidence (its map does not overlap the global map there yet, or the
  /// map check is inconclusive): still a fair guess, which active linking may act on.
  bool plausible = false;
};

/// The pose-graph edge of a loop closure: its covariance inverted (identity if not positive definite).
PoseGraphEdge loop_edge(const LoopClosure& c);
/// The same closure seen from b (a and b swapped, transform inverted, covariance rotated into b).
LoopClosure reversed(const LoopClosure& c);

class RobotLinker {
 public:
  explicit RobotLinker(const MapperOptions& options = {});

  /// Notes a keyframe just stored in data: queued for loop detection, its landmark observations
  /// added to its robot's local landmarks. Before the first update() the lowest robot seen anchors
  /// provisionally (data.starts), so its keyframes are placed at once; true when that moved.
  bool note_keyframe(const Keyframe& kf, MapperData* data);
  /// Every link decision, in this order: commit the anchor, marker links, sighting links, the
  /// operator's alignments, loop detection (intra closures gated, inter-robot ones queued for
  /// PCM), unlinked robots' own frames, scan links of
  /// robot pairs, placing newly linked robots (data.starts), then closures held until both robots
  /// were placed.
  LinkUpdate update(MapperData* data);

  const LinkStats& stats() const { return stats_; }
  const KeyframeLoopCloserStats& loop_closer_stats() const { return loop_closer_.stats(); }
  /// The operator placed `robot`'s own map at T_global_local: judged at the next update().
  void request_alignment(RobotId robot, const SE2& T_global_local);
  /// Every robot's latest alignment and its verdict.
  const std::map<RobotId, AlignmentVerdict>& alignments() const { return alignments_; }
  /// Marker- and sighting-based link decisions so far (accepted ones and the latest refusal per pair).
  const std::vector<LinkEvent>& landmark_link_events() const { return landmark_link_events_; }

 private:
  void choose_anchor(MapperData* data);
  RobotId component_of(const MapperData& data, RobotId robot) const;
  /// Joins the components of ra and rb; the anchor's component keeps its root.
  void join_components(const MapperData& data, RobotId ra, RobotId rb);
  void detect_new_loops(MapperData* data, LinkUpdate* update);
  /// The chi-square of an inter-robot closure against the entry hints (robot_linker_checks.cpp):
  /// the start it implies for an unplaced hinted robot, from the other robot's placement (or hint,
  /// variances added), against that robot's hint. nullopt when no hint applies.
  std::optional<double> hint_chi2(const MapperData& data, const LoopClosure& c) const;
  /// Re-solves the own frame of each unlinked robot whose accepted intra-robot closures changed.
  void refresh_own_frames(MapperData* data) const;
  void link_robot_pairs(MapperData* data, LinkUpdate* update);
  /// PCM clique -> spread -> map check for one unlinked pair; true when the pair got linked.
  bool try_link_pair(MapperData* data, RobotId ra, RobotId rb, std::vector<LoopClosure>* candidates,
                     LinkUpdate* update);
  void place_new_robots(MapperData* data, LinkUpdate* update) const;
  /// Judges the held closures whose robots are now placed.
  void release_held_closures(MapperData* data, LinkUpdate* update);
  // Markers (robot_linker_landmarks.cpp).
  void link_by_landmarks(MapperData* data, LinkUpdate* update);
  /// Links ra and rb on shared landmarks when the alignment and the map check allow; true if linked.
  bool try_link_by_landmarks(MapperData* data, RobotId ra, RobotId rb, LinkUpdate* update);
  /// Links unlinked pairs on their sightings of each other (sightings.h), judged as markers are.
  void link_by_sightings(MapperData* data, LinkUpdate* update);
  /// False while the pair was judged fewer than LandmarkOptions::retry_observations ago; else
  /// records `observations` as the pair's latest judgement.
  bool due_for_judging(std::map<std::pair<RobotId, RobotId>, int>* judged_at, std::pair<RobotId, RobotId> pair,
                       int observations) const;
  /// Aligns the points known in both frames (entry i of la and lb is one point), then the map
  /// check; links when both allow. `kind` names the evidence in the decision ("markers").
  bool try_link_on_points(MapperData* data, RobotId ra, RobotId rb, const LocalLandmarks& la, const LocalLandmarks& lb,
                          const std::string& kind, LinkUpdate* update);
  // The operator's alignments (robot_linker_operator.cpp).
  void judge_alignments(MapperData* data, LinkUpdate* update);
  /// judge_placement of the operator's alignment; links rb when it is accepted.
  void judge_alignment(MapperData* data, AlignmentVerdict* verdict, LinkUpdate* update);
  /// A placement hypothesis of unlinked rb in the global frame, judged: verified matches around it
  /// (o.search), their rigid fit, the matches that agree with it, the map check. `what` names the
  /// hypothesis in the reason ("the alignment").
  struct PlacementJudgement {
    bool accepted = false;
    bool plausible = false;  ///< refused only for want of evidence (AlignmentVerdict::plausible)
    std::string reason;
    SE2 placed;                                 ///< accepted: T_global_local the agreeing matches give
    std::vector<LoopClosure> agreeing, guided;  ///< a on the placed side
  };
  PlacementJudgement judge_placement(const MapperData& data, RobotId rb, const SE2& T_global_local,
                                     const OperatorAlignmentOptions& o, const std::string& what) const;
  /// Links rb to the anchor's component by an accepted judgement: its matches join data->loops.
  void link_placement(MapperData* data, RobotId rb, const PlacementJudgement& j, LinkUpdate* update);
  // Entry hints (robot_linker_hints.cpp).
  /// Searches around every tight entry hint of an unlinked robot, when due.
  void search_entry_hints(MapperData* data, LinkUpdate* update);
  /// Sigmas within MapperOptions::tight_hint_max_sigma_*.
  bool is_tight(const EntryHint& hint) const;
  /// Whether each closure of the clique is also the match found within the hints' sigmas of where
  /// the placements and tight hints put its keyframes (a clique from one spot may be a look-alike
  /// spot a metre off, which the hint's chi-square gate passes; see MapperOptions::entry_hint_chi2).
  bool hint_confirms(const MapperData& data, const std::vector<LoopClosure>& clique) const;
  /// Where keyframe `id` lies in the global frame: under its robot's placement (variances 0), or
  /// else its entry hint (a tight one only, with `tight_only`) and the hint's variances; nullopt
  /// when neither places it.
  struct HintedPose {
    SE2 T_global;
    double var_xy_m2 = 0.0, var_yaw_rad2 = 0.0;
  };
  std::optional<HintedPose> placed_or_hinted(const MapperData& data, KeyframeId id, bool tight_only) const;
  // Checks of link hypotheses and closures (robot_linker_checks.cpp).
  /// Why the clique `closures` (a = ra, b = rb) covers too little of a trajectory; empty if not.
  std::string spread_deficit(const MapperData& data, const std::vector<LoopClosure>& closures) const;
  /// The clique's link as T_A_blocal (A: the global frame when ra is placed, else ra's local
  /// frame): the best rigid fit of both keyframes of every closure when either side's spans
  /// min_link_spread_m, else the mean of the closures' transforms.
  SE2 link_hypothesis(const MapperData& data, RobotId ra, const std::vector<LoopClosure>& closures) const;
  /// Map check of the clique as a link of rb to ra (accepted, or the reason): rb placed rigidly by
  /// the clique; if that is refuted by a near miss (GuidedLinkOptions::max_rigid_contradiction_ratio),
  /// or always with GuidedLinkOptions::on_every_link, placed by the clique and the guided search's
  /// closures (ev.guided), whose verdict then counts only if it accepts (on_every_link: always).
  LinkEvent judge_link(const MapperData& data, RobotId ra, RobotId rb, const std::vector<LoopClosure>& closures) const;
  /// How far closure c (a = ra) is off the link T_A_blocal, in units of the linked-pair gate.
  double link_misfit(const MapperData& data, RobotId ra, const SE2& T_A_blocal, const LoopClosure& c) const;
  /// Whether an inter-robot closure between two robots of one component may join the graph
  /// (held while either robot is unplaced).
  bool accept_linked_pair_closure(const MapperData& data, const LoopClosure& c, LinkUpdate* update);
  /// Whether a closure within one robot agrees with its own local poses up to its possible drift.
  bool accept_intra_robot_closure(const MapperData& data, const LoopClosure& c);
  /// The closure from `id`'s robot's first keyframe to `id`, when `id` is one StartClosureOptions
  /// names and the first scan verifies in its local map (robot_linker_start.cpp).
  std::optional<LoopClosure> start_closure(const MapperData& data, KeyframeId id) const;
  // Guided search around a link hypothesis (robot_linker_guided.cpp).
  /// Verified closures (a in frame A, b = rb) between rb's keyframes placed by T_A_blocal and the
  /// nearest keyframes of frame A, each searched in a small window around the hypothesis.
  std::vector<LoopClosure> guided_closures(const MapperData& data, RobotId ra, RobotId rb, const SE2& T_A_blocal) const;
  /// The same with other search options (the operator's alignment).
  std::vector<LoopClosure> guided_closures(const MapperData& data, RobotId ra, RobotId rb, const SE2& T_A_blocal,
                                           const GuidedLinkOptions& options) const;
  /// rb's keyframes in frame A solved against the clique and the guided closures (a in frame A,
  /// held fixed), keeping rb's own map as stiff as its front end's uncertainty says. Guided closures
  /// the solution leaves off by more than GuidedLinkOptions::max_residual_* are dropped from *guided.
  PlacedScans tentative_placement(const MapperData& data, RobotId ra, RobotId rb, const SE2& T_A_blocal,
                                  const std::vector<LoopClosure>& clique, std::vector<LoopClosure>* guided) const;

  MapperOptions options_;
  bool anchor_committed_ = false;
  KeyframeLoopCloser loop_closer_;
  std::vector<KeyframeId> detect_queue_;
  std::map<std::pair<RobotId, RobotId>, std::vector<LoopClosure>> inter_candidates_;  ///< a = lower id
  std::map<RobotId, RobotId> component_parent_;
  LinkStats stats_;
  /// Inter-robot closures between robots of one component not yet placed: judged once placed.
  std::vector<LoopClosure> held_closures_;
  std::map<std::pair<RobotId, RobotId>, std::string> last_verdict_;  ///< dedupes link events
  std::map<RobotId, int> landmark_observations_;                     ///< valid observations per robot
  /// Per unlinked pair: observations of both robots when last judged (retry gate).
  std::map<std::pair<RobotId, RobotId>, int> landmark_pair_judged_at_;
  std::vector<LinkEvent> landmark_link_events_;
  std::map<RobotId, int> sighting_counts_;  ///< sightings each robot made
  std::map<RobotId, AlignmentVerdict> alignments_;
  std::map<std::pair<RobotId, RobotId>, int> sighting_pair_judged_at_;
  std::map<RobotId, size_t> hint_searched_at_;    ///< keyframes stored at each robot's last hint search
  std::map<RobotId, std::string> hint_verdicts_;  ///< each robot's last hint search verdict (dedupes events)
};

}  // namespace cairn::base
