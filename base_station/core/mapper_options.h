#pragma once
// Options of the base station's MultiRobotMapper, with defaults that suit the simulator and
// indoor rescue scenes.
#include <cmath>

#include "base_station/core/global_map_renderer.h"
#include "base_station/core/global_object.h"
#include "base_station/core/keyframe_loop_closer.h"
#include "base_station/core/keyframe_pose_graph.h"
#include "base_station/core/landmarks.h"
#include "base_station/core/map_consistency.h"
#include "base_station/core/object_constraints.h"
#include "base_station/core/pcm.h"
#include "common/occupancy_grid.h"

namespace cairn::base {

/// Guided search around a link hypothesis whose rigid placement the map check refutes by a near
/// miss (robot_linker_guided.cpp): the hypothesis is judged again as the closures found
/// around it place the new robot, and those closures join the graph if it is accepted. Only then: on the
/// simulated demo, where every link passes rigidly, adding them to every link moved the robots from
/// 0.089-0.102 to 0.109-0.135 m RMSE (the closures are right to 5 mm; the simulated robots' own
/// maps share a bias that more ties spread into the anchor's map).
struct GuidedLinkOptions {
  bool enabled = true;
  /// Search around every hypothesis, and judge and link by the guided placement whenever closures
  /// are found (false: only after a rigid refusal, above). Real logs gain a little (Intel split
  /// 0.088 -> 0.085 m merged ATE), the demo loses 0.02 m.
  bool on_every_link = false;
  /// The second chance is for near misses only: a rigid placement refuted with a contradiction
  /// ratio above this (twice the map check's limit) is wrong, not drifted (MIT CSAIL's true links
  /// 6.0 % and 7 %; its wrong hypotheses 38-63 %, Intel's 21-30 %, the look-alike wings' 2-6 %
  /// refuted by their pieces). A refusal for a large wall piece alone still gets it.
  double max_rigid_contradiction_ratio = 0.12;
  double sample_spacing_m = 1.0;             ///< one query keyframe of the new robot per this much of its path
  int max_verifications = 150;               ///< per hypothesis, spread evenly over the queries
  double max_distance_m = 1.5;               ///< the nearest keyframe of the placed side within this ...
  double max_yaw_difference_rad = M_PI / 2;  ///< ... and heading the same way give or take this
  /// A guided closure the tentative placement (the new robot solved against the clique and every
  /// guided closure) leaves off by more than this is dropped: on the Intel split one 0.88 m off the
  /// reference was left 0.59 m off, the right ones at most 0.27 m / 1.5 deg.
  double max_residual_m = 0.2;
  double max_residual_rad = 0.035;
  /// Each query's linear window grows by this per metre of its keyframe from its robot's start (a
  /// heading error's lever arm: 0.17 m per metre for 10 deg), up to max_linear_window_m. 0: fixed.
  double linear_window_m_per_m = 0.0;
  double max_linear_window_m = 4.0;
  /// Windows around the hypothesis: a robot's own drift (decimetres, a few degrees), not aliasing.
  LoopVerifierOptions verifier = [] {
    LoopVerifierOptions o;
    o.linear_window_m = 0.5;
    o.angular_window_rad = 0.1;
    return o;
  }();
};

/// Closures from each robot's first keyframe to its keyframes soon after (robot_linker_start.cpp).
/// The first keyframe is where the robot entered (the anchor's is the world's origin), and its
/// edges to the next are its local SLAM's weakest: turning in place against a submap of one or a
/// few scans, the 1-degree beams alias and the heading comes out 0.3-1.3 deg off (docs/benchmarks.md
/// "Where that heading error comes from"), which turns everything after it. The first scan matched
/// (scan points and ICP, not a grid) into the local maps of later keyframes measures that heading
/// directly; nothing else does until the robot comes back.
struct StartClosureOptions {
  int every_keyframes = 8;      ///< keyframes seq k x this (k >= 1) after the first ...
  int max_keyframes = 64;       ///< ... up to this many after it ...
  double max_distance_m = 4.0;  ///< ... and within this of it (its robot's own poses) are tried
  /// Windows around the robot's own estimate: its start-up heading error, not aliasing.
  LoopVerifierOptions verifier = [] {
    LoopVerifierOptions o;
    o.linear_window_m = 0.3;
    o.angular_window_rad = 0.06;  // 3.4 deg
    return o;
  }();
};

/// The operator's alignment of an unlinked robot's map in the console (robot_linker_operator.cpp):
/// a hypothesis searched around with windows for a hand's error, not a robot's drift.
struct OperatorAlignmentOptions {
  /// Any heading (360 deg scans) and keyframes up to 6 m apart: two robots' maps overlap where
  /// their lasers reached, often metres from where either drove.
  GuidedLinkOptions search = [] {
    GuidedLinkOptions o;
    o.sample_spacing_m = 0.5;
    o.max_distance_m = 6.0;
    o.max_yaw_difference_rad = M_PI;
    o.verifier.linear_window_m = 1.5;
    o.verifier.angular_window_rad = 0.35;  // 20 deg
    return o;
  }();
  int min_closures = 3;  ///< verified matches that agree with each other, needed before the map check
};

/// A tight entry hint searched as the operator's alignment is (robot_linker_hints.cpp): Scan
/// Context finds closures only where two robots stood in nearly the same spot; the hint says where
/// to look, and scan matches between keyframes up to 6 m apart are found around it. Only tight
/// hints (MapperOptions::tight_hint_max_sigma_*) are searched, with windows of 3 sigma in position
/// (widened by 2 sigma of heading per metre of the keyframe from its robot's start: the heading's
/// lever arm) and 2 sigma in heading (set from each hint over search.search.verifier); the
/// placement found must still agree with the hint (MapperOptions::entry_hint_chi2) and pass the
/// map check.
struct EntryHintSearchOptions {
  bool enabled = true;
  /// A robot's hint is searched again once this many keyframes (of any robot) arrived since its last
  /// search: each search costs up to search.search.max_verifications scan matches.
  int retry_after_keyframes = 8;
  OperatorAlignmentOptions search = [] {
    OperatorAlignmentOptions o;
    o.search.max_verifications = 40;
    return o;
  }();
};

struct MapperOptions {
  OccupancyGridOptions grid;  ///< global map; resolution 0.05 m by default
  /// Max-range beams (no return) clear free space up to min(scan range_max, this).
  double no_return_clear_range_m = 10.0;

  KeyframePoseGraphOptions graph;  ///< robust losses per edge kind (Cauchy on loops)
  PoseGraphSolveOptions solve;
  /// Prior pinning each linked robot's first keyframe at T_global_local * T_local_base(first).
  double start_prior_sigma_xy_m = 0.01;
  double start_prior_sigma_yaw_rad = 0.005;
  /// When a keyframe's predecessor (seq-1) has not arrived, it is linked to the nearest earlier
  /// keyframe by the difference of their local poses, with this uncertainty per missing step.
  double gap_sigma_xy_m_per_step = 0.05;
  double gap_sigma_yaw_rad_per_step = 0.02;
  /// No chain edge is taken as surer than this (its covariance's diagonal raised to it): an agent's
  /// edge of a robot turning in place on odometry alone came with 1e-18 m^2 (information 4e17), and
  /// the pose graph could no longer converge after a link: in CI a robot whose five inter-robot
  /// closures were right was left 6 m off. Matched edges carry the agent's 1 cm / 0.57 deg floor.
  double chain_edge_min_sigma_xy_m = 0.01;
  double chain_edge_min_sigma_yaw_rad = 0.01;

  /// Automatic merging: place recognition + verification (keyframe_loop_closer.h), PCM on each robot
  /// pair's inter-robot closures before the pair is first linked (pcm.h).
  bool detect_loops = true;
  KeyframeLoopCloserOptions loop_closer;
  PcmOptions pcm;
  /// Mutually consistent inter-robot closures needed to link two robots for the first time.
  int min_link_clique = 3;
  /// A linking clique's closures must come from distinct places: the keyframes they join span at
  /// least this (largest pairwise distance) on one robot's trajectory at least. Their lever arm then
  /// pins the link's rotation (link_hypothesis fits both keyframes of every closure); whether the
  /// place is aliased is the map check's to say. (On both sides, MIT CSAIL's middle robot, which
  /// sees robot 0's corridor junction from 5.9 m of its own path, 0.6 m of robot 0's, never links.)
  double min_link_spread_m = 2.0;
  /// Entry hints (MultiRobotMapper::set_entry_hint): an inter-robot closure whose implied start of
  /// the hinted robot is off the hint by more than this chi-square (3 dof, 99 %: 11.34; sigmas from
  /// the hint) is refused before PCM. A tight hint (sigmas within the two bounds below) is also
  /// searched around (entry_hint_search), and a clique under it needs no min_link_spread_m when
  /// each of its closures is also the match found around the hint (a window of the hints' sigmas):
  /// robots that enter side by side down one corridor see the same walls from spots 1.25 m apart,
  /// and a clique from one spot that the hint's gate let through (it passes 1.7 m at 0.5 m sigma)
  /// placed a robot 1.25 m off for seconds in 4 of 7 building-site missions (bench_link_replay).
  /// A looser hint (1 m / 20 deg) lets the gate pass a look-alike 3 m and 60 deg off: it only
  /// narrows the search.
  double entry_hint_chi2 = 11.34;
  double tight_hint_max_sigma_xy_m = 0.5;
  double tight_hint_max_sigma_yaw_rad = 10.0 * M_PI / 180.0;
  /// Map-level check of every link hypothesis (map_consistency.h) over all keyframes seen so far;
  /// a refuted clique's closures are dropped. Also applied to an inter-robot closure into an
  /// already linked pair when it disagrees with the current estimate by more than the gate below.
  bool check_map_consistency = true;
  MapConsistencyOptions map_check;
  GuidedLinkOptions guided_link;
  OperatorAlignmentOptions operator_alignment;
  EntryHintSearchOptions entry_hint_search;
  StartClosureOptions start_closures;
  double linked_closure_gate_m = 0.3;
  double linked_closure_gate_rad = 0.1;
  /// ...but one that disagrees by more than this is no drift correction of the linked robots: it is
  /// dropped without a map check. In bench_merger_scale's world of identical rooms the local map
  /// check passed 83 closures 11-63 m off with 90 or 180 deg turns (one at 0.x m), and on Intel
  /// split into 4 robots one 28.9 m / 90 deg off when the refinement was capped at 5 iterations.
  double linked_closure_max_correction_m = 5.0;
  double linked_closure_max_correction_rad = 0.5;
  /// A closure within one robot's trajectory must agree with the robot's keyframe poses as its
  /// agent last estimated them (MultiRobotMapper::agent_local_pose: loop-closed once the agent sent
  /// KeyframePoses, else the front end's) up to the drift its SLAM can have accumulated between
  /// the two keyframes:
  /// base + per metre of path travelled between them. Look-alike rooms otherwise give verified
  /// closures that are metres off and all agree with each other, and the robust loss alone then
  /// decides by the start of the solve which cluster wins (the two-robot mission under CPU load:
  /// 26 closures 5 m off, robots placed 4-5 m wrong).
  double intra_closure_gate_m = 0.5;
  double intra_closure_gate_m_per_m = 0.01;
  double intra_closure_gate_rad = 0.1;
  double intra_closure_gate_rad_per_m = 0.005;
  /// Max Ceres iterations of an incremental update (warm-started); a full re-solve with LAGO
  /// initialisation (solve.max_iterations) runs when robots are first linked.
  int incremental_max_iterations = 10;
  /// An incremental update solves a window only: the new keyframes plus this many placed
  /// predecessors on their robot, and around each new loop edge's ends this many keyframes before
  /// them to the end of their trajectories; the rest of the graph is held constant. Exact for new
  /// odometry (a leaf does not move the optimum of the others); after loop closures, full
  /// warm-started solves of incremental_max_iterations follow on each update until one converges.
  int incremental_window_keyframes = 10;
  /// Keep the pose graph and its Ceres problem alive between updates (0.3 ms per update at 10,000
  /// keyframes, bench_merger_scale). Off = the graph is rebuilt every update from the last solution
  /// (O(keyframes) per update; ~45 ms at 5,000). Both give the same maps: the load-dependent
  /// 4-5 m error once blamed on the live graph was wrong intra-robot closures (intra_closure_gate_m).
  bool incremental_graph = true;
  /// Window solves for odometry-only updates (above). When false every update is a warm-started
  /// solve of the whole graph (incremental_max_iterations).
  bool windowed_updates = true;
  /// While keyframes keep arriving, those full refinement solves run at most once every this many
  /// updates (new loop edges join the graph at once; between refinements only the windows of the
  /// new keyframes are solved). An update without new keyframes refines at once, so an idle base
  /// still converges to the full-solve optimum. A full solve costs O(keyframes) or worse (many
  /// loops fill in the factorisation: ~0.9 s at 7,000 keyframes in bench_merger_scale --loops);
  /// with frequent loops (10 robots revisiting rooms: a new loop edge on most updates) refining on
  /// every update dominated the update at scale. 1 = every update.
  int refine_every_updates = 10;
  /// ... and at most once every (graph nodes / this) updates, so that the amortised cost of those
  /// O(keyframes)-or-worse solves stays bounded on large graphs (every 100 updates at 10,000
  /// keyframes, 200 at 20,000). 0 = refine_every_updates only.
  int refine_keyframes_per_update = 100;
  /// Optional wall-time cap of those refinement solves (0 = none). Off by default: a time cap makes
  /// the result depend on the machine's load (under ctest -j2 the two-robot mission exported a
  /// half-refined graph, 4-5 m off), and the mapper must stay deterministic.
  double refine_max_time_s = 0.0;
  /// Incremental rendering of the global map (re-render tiles of moved keyframes).
  GlobalMapRenderOptions map_render;

  /// Upper bound of the duplicate-merge candidate gate on centroid distance (same class).
  double merge_distance_m = 0.75;
  /// Voxel size of the merged object clouds (global frame).
  double object_voxel_m = 0.02;
  /// Duplicate merging: overlap candidates verified by RGB-ICP (global_object.h); its max_gate_m and
  /// object_voxel_m are taken from the two fields above.
  ObjectMergeOptions object_merge;
  /// Merged objects seen from two or more anchor keyframes (two robots, or one robot twice) become
  /// point nodes of the pose graph observed from their anchors (object_constraints.h). They only
  /// constrain robots already linked; they never link robots.
  ObjectConstraintOptions object_constraints;

  /// Identified landmarks (markers) in keyframes: landmark nodes with range-bearing residuals, and
  /// marker-based link hypotheses for robot pairs not linked yet (landmarks.h).
  LandmarkOptions landmarks;
};

}  // namespace cairn::base
