#pragma once
// Map-level consistency check of a link hypothesis between two groups of keyframes (two robots, or
// a robot and the already-merged component), used by the merger before it first links a robot pair
// and before it accepts an inter-robot closure that moves a linked pair: perceptual aliasing
// (near-identical wings of a building) yields closures that are mutually consistent, so PCM alone
// cannot reject them, but the two maps placed by the wrong transform contradict each other
// elsewhere (a corridor one robot saw as free is crossed by the other's walls).
// Method: each side's keyframe scans are ray-cast into a coarse log-odds grid in a common frame
// (side B moved by the hypothesis); a wall cell of one side (confidently occupied) that falls where
// the other side saw confidently free space, with no wall of that side within a tolerance, is a
// contradiction ("B's endpoint in A's free space" and, by symmetry, "B's free ray through A's wall").
// Only walls seen from close by (wall_max_range_m) accuse: a far wall carries the heading error of
// the keyframe that saw it, which put correct links at 3-6 % with 12-26-cell pieces in the collapsed
// demo (0.0-0.3 % once only near walls count).
// Refuted when the ratio contradictions / wall cells of either side that fall in the other side's
// observed area is high (free-free agreement is not counted: it would dilute the evidence), or
// when one connected piece of contradicting wall is long (localised, structural disagreement). In the
// spirit of the map-consistency tests of Olson's "Recognizing places using spectrally clustered
// local matches" (RAS 2009) and the free-space "explanation" checks of Kuemmerle et al. (ICRA 2008).
#include <cstdint>
#include <string>
#include <vector>

#include "common/keyframe.h"
#include "common/se2.h"

namespace cairn::base {

struct MapConsistencyOptions {
  double resolution_m = 0.10;      ///< cell size of the comparison grids
  double max_range_m = 10.0;       ///< beams cut to this length (no-return beams clear up to it)
  float occupied_log_odds = 0.5f;  ///< a cell at or above is a wall
  float free_log_odds = -1.5f;     ///< a cell at or below is confidently free
  double tolerance_m = 0.30;       ///< a wall within this of the other side's wall agrees
  /// Only wall cells a beam of at most this length ended in are checked against the other side's
  /// free space (0 = all). A wall seen only from far away is placed by the yaw of one distant
  /// keyframe (0.1 rad is 0.8 m at 8 m), so it still excuses the other side's walls near it but does
  /// not accuse the other side's free space.
  double wall_max_range_m = 5.0;
  int min_checked_cells = 60;  ///< fewer overlapping wall cells: inconclusive (not refuted)
  /// Above this the hypothesis is refuted. Office simulation: right links 0.01, aliased ones 0.13-0.32.
  double max_contradiction_ratio = 0.06;
  /// A connected piece of wall this large (cells) in the other side's confident free space refutes
  /// the hypothesis whatever the ratio: aliased wings agree almost everywhere, and differ only
  /// where the building does (a corridor's end wall), which a ratio over the whole map dilutes.
  int max_contradiction_cluster_cells = 10;
  /// A large piece is excused ("explained") when the other side, whose beams passed through it,
  /// also saw what lies behind it where this side mapped walls: at least this fraction of its
  /// returned beams through the piece end within tolerance_m of this side's walls (pooled over the
  /// large pieces, at least explained_min_beams beams). Then both robots agree on the room and the
  /// piece is an object that was there for one visit only (a door leaf, a moved cabinet), not a
  /// misplaced map: a wrong placement also moves what lies behind. Measured on the wall pieces
  /// that refuted links: raw MIT CSAIL's true robot 0-2 link 69 %, its wrong hypotheses 26-35 %,
  /// the simulated look-alike wings 0-7 % (docs/benchmarks.md). 0 = never excused.
  double explained_min_fraction = 0.6;
  int explained_min_beams = 10;
  /// Local checks (select_near_keyframes; the merger's check of a closure into an already linked
  /// pair): only keyframes whose position in the common frame lies within this of the checked
  /// place take part, so the cost of a check does not grow with the map. An aliased closure is
  /// refuted where the two copies differ near it (a scan reaches max_range_m, so walls up to
  /// radius + max_range_m are compared); 0 = the merger checks the whole map (no selection). Cost
  /// and aliasing measured in docs/benchmarks.md (issue 4, bench_merger_scale --loops).
  double local_radius_m = 15.0;
  /// Of those, one keyframe per cell of this size (the one nearest the place): a place revisited
  /// many times costs as much as one pass through it. 0 = no thinning.
  double local_thin_cell_m = 0.5;
  /// At most this many keyframes per side (the nearest first): bounds the cost in dense maps.
  int local_max_keyframes = 400;
};

struct MapConsistencyResult {
  bool consistent = true;       ///< false: the hypothesis is refuted by the maps
  bool conclusive = false;      ///< enough overlap to judge
  int checked_cells = 0;        ///< wall cells of either side inside the other side's observed area
  int contradicting_cells = 0;  ///< of those, in the other side's confident free space
  double contradiction_ratio = 0.0;
  int largest_contradiction_cells = 0;  ///< largest 8-connected piece of contradicting wall not explained
  int explained_pieces = 0;             ///< large pieces excused (MapConsistencyOptions::explained_min_fraction)
  std::string reason;                   ///< set when refuted or inconclusive
};

/// One side's keyframes with their poses in the common frame.
struct PlacedScans {
  std::vector<const Keyframe*> keyframes;
  std::vector<SE2> T_frame_base;  ///< same length
};

/// The keyframes of `side` that a local check around `center_m` (common frame) uses: within
/// options.local_radius_m, thinned to one per local_thin_cell_m cell, at most local_max_keyframes,
/// nearest first (ties by input order, so the selection is deterministic).
PlacedScans select_near_keyframes(const PlacedScans& side, const Eigen::Vector2d& center_m,
                                  const MapConsistencyOptions& options = {});

/// Compares side `a` with side `b` (both already placed in one frame by the hypothesis).
MapConsistencyResult check_map_consistency(const PlacedScans& a, const PlacedScans& b,
                                           const MapConsistencyOptions& options = {});

/// A check drawn for people (diagnostics: why two maps were judged to contradict), north up, one
/// pixel per cell of options.resolution_m: white unknown; side a's confident free space light blue,
/// b's light orange, both light green; a's walls dark red, b's dark blue; contradicting walls
/// bright green (a's wall in b's free space) and orange (b's wall in a's free space); keyframe
/// positions purple (a) and teal (b).
struct MapConsistencyImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< row-major, top row first, 3 bytes per pixel
};
MapConsistencyImage draw_map_consistency(const PlacedScans& a, const PlacedScans& b,
                                         const MapConsistencyOptions& options = {});

}  // namespace cairn::base
