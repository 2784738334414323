// Real multi-robot merging (the "Real multi-robot" criterion): raw MIT CSAIL split into 3
// robots and the Intel lab (corrected log + seeded odometry noise, 10 % / 3 deg per m) into 4, each
// a contiguous segment starting at its own origin, replayed through AgentPipelines; the base's
// MultiRobotMapper knows robot 0's start only. Asserts: every robot linked; no accepted inter-robot
// closure off the reference by more than 0.3 m / 5 deg (RobotRun::closure_reference:
// the nearest measured reference pose, carried by the agent's own poses); merged ATE (one SE2
// alignment of the whole map) at most 1.5x the single-robot run's.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "base_station/export/exporter.h"
#include "tests/multirobot/loop_funnel.h"
#include "tests/multirobot/split_run.h"

namespace cairn::multirobot {
namespace {

const std::string kData = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/";
constexpr double kMaxClosureErrorM = 0.3;
constexpr double kMaxClosureErrorRad = 5.0 * M_PI / 180.0;

/// The reference frame <- robot's local frame, by the best alignment of its whole trajectory (the
/// reference of a single keyframe is not enough: at the start of the MIT log it is carried over
/// 60 scans by raw odometry, and the robot's own first keyframes can be its worst).
SE2 reference_from_local(const RobotRun& run, double* own_ate_m) {
  std::vector<Eigen::Vector2d> est, ref;
  for (size_t i = 0; i < run.keyframes.size(); ++i) {
    est.push_back(run.keyframes[i].T_local_base.translation());
    ref.push_back(run.reference[i].translation());
  }
  const SE2 T = align_points_2d(est, ref);
  double se = 0;
  for (size_t i = 0; i < est.size(); ++i) se += (T * est[i] - ref[i]).squaredNorm();
  *own_ate_m = est.empty() ? 0.0 : std::sqrt(se / double(est.size()));
  return T;
}

/// Robot k placed in robot 0's frame by the reference, and the map check's verdict on that link
/// (also drawn: draw_map_consistency, PNG in the test's temporary folder).
void print_true_link(const std::vector<RobotRun>& runs, size_t k, const char* name) {
  double ate0 = 0, atek = 0;
  const SE2 T = reference_from_local(runs[0], &ate0).between(reference_from_local(runs[k], &atek));
  base::PlacedScans a, b;
  for (const Keyframe& kf : runs[0].keyframes) a.keyframes.push_back(&kf), a.T_frame_base.push_back(kf.T_local_base);
  for (const Keyframe& kf : runs[k].keyframes)
    b.keyframes.push_back(&kf), b.T_frame_base.push_back(T * kf.T_local_base);
  const base::MapConsistencyResult m = base::check_map_consistency(a, b, base::MapperOptions().map_check);
  const base::MapConsistencyImage img = base::draw_map_consistency(a, b, base::MapperOptions().map_check);
  const std::string png = ::testing::TempDir() + "mapcheck_" + name + "_0-" + std::to_string(k) + ".png";
  std::string error;
  if (base::write_rgb_png(img.width, img.height, img.rgb, png, &error))
    std::printf("[%s] drawn: %s\n", name, png.c_str());
  std::printf("[%s] true link 0-%zu: (%.2f %.2f %.2f), own ATE %.3f / %.3f m, map check: %s (%.3f, piece %d)\n", name,
              k, T.x(), T.y(), T.yaw(), ate0, atek, m.consistent ? "consistent" : "refuted", m.contradiction_ratio,
              m.largest_contradiction_cells);
}

/// Runs the split and checks it: every robot in the anchor's map, every accepted inter-robot
/// closure within 0.3 m / 5 deg of the reference, merged ATE at most 1.5x the single-robot run's.
void check_split(const ReplayLog& log, int robots, const char* name, const base::MapperOptions& options = {}) {
  // Single-robot baseline: the whole log as one robot through the same agent and base.
  const std::vector<RobotRun> single = run_split(log, 1);
  base::MultiRobotMapper single_mapper(options);
  merge(single, &single_mapper);
  int single_matched = 0;
  const double single_ate = merged_ate_m(single, single_mapper, &single_matched);

  const std::vector<RobotRun> runs = run_split(log, robots);
  for (const RobotRun& r : runs) {
    for (size_t i = 0; i < r.keyframes.size(); ++i) {
      ASSERT_EQ(r.keyframes[i].id.seq, int32_t(i));
      ASSERT_TRUE(r.reference[i].vector().allFinite()) << "no reference for " << to_string(r.keyframes[i].id);
    }
  }
  // Optional diagnostics (CAIRN_MULTIROBOT_FUNNEL=1): what the map check says of each true link.
  if (std::getenv("CAIRN_MULTIROBOT_FUNNEL")) {
    for (int k = 1; k < robots; ++k) print_true_link(runs, size_t(k), name);
  }
  // Optional diagnostics (CAIRN_MULTIROBOT_FUNNEL=1): true inter-robot candidates at each stage.
  if (std::getenv("CAIRN_MULTIROBOT_FUNNEL")) {
    for (const FunnelRow& row : loop_funnel(runs, base::MapperOptions().loop_closer)) {
      std::printf("[%s] funnel %s\n", name, to_string(row).c_str());
    }
    if (std::string(std::getenv("CAIRN_MULTIROBOT_FUNNEL")) == "only") GTEST_SKIP() << "funnel only";
  }
  base::MultiRobotMapper mapper(options);
  const MergeStats stats = merge(runs, &mapper);
  for (const base::LinkEvent& e : stats.link_events) {
    int true_members = 0;  // members agreeing with the reference (0.3 m / 5 deg)
    std::string errors;    // each member's error against the reference, m/deg
    for (const base::LoopClosure& c : e.members) {
      const ClosureError err = closure_error(c, runs);
      true_members += err.translation_m <= kMaxClosureErrorM && err.rotation_rad <= kMaxClosureErrorRad;
      char buf[48];
      std::snprintf(buf, sizeof(buf), " %.2f/%.1f", err.translation_m, err.rotation_rad * 180 / M_PI);
      errors += buf;
    }
    int guided_off = 0;  // guided closures (MapperOptions::guided_link) off the reference
    double guided_worst_m = 0.0;
    for (const base::LoopClosure& c : e.guided) {
      const ClosureError err = closure_error(c, runs);
      guided_off += err.translation_m > kMaxClosureErrorM || err.rotation_rad > kMaxClosureErrorRad;
      guided_worst_m = std::max(guided_worst_m, err.translation_m);
    }
    std::printf(
        "[%s] link event: robot %d - robot %d, %d closures (%d true:%s), %zu guided (%d off, worst %.2f m), %s\n", name,
        e.robot.value, e.other.value, e.closures, true_members, errors.c_str(), e.guided.size(), guided_off,
        guided_worst_m, e.reason.c_str());
    if (e.accepted) std::printf("[%s]   map contradiction %.1f %%\n", name, 100.0 * e.contradiction_ratio);
    if (e.rigid_contradiction_ratio >= 0)
      std::printf("[%s]   rigid placement %.1f %%\n", name, 100.0 * e.rigid_contradiction_ratio);
  }
  int linked = 0;
  std::string unlinked;
  for (int k = 0; k < robots; ++k) {
    if (mapper.linked(RobotId(k)))
      ++linked;
    else
      unlinked += " " + std::to_string(k);
  }
  EXPECT_EQ(linked, robots) << name << ": robots not linked:" << unlinked;
  if (std::getenv("CAIRN_MULTIROBOT_FUNNEL")) {  // each robot's map as the base refined it, against the reference
    for (int k = 0; k < robots; ++k) {
      std::vector<Eigen::Vector2d> est, ref;
      for (size_t i = 0; i < runs[size_t(k)].keyframes.size(); ++i) {
        est.push_back(mapper.refined_local_pose(runs[size_t(k)].keyframes[i].id).translation());
        ref.push_back(runs[size_t(k)].reference[i].translation());
      }
      const SE2 T = align_points_2d(est, ref);
      double se = 0, worst = 0;
      for (size_t i = 0; i < est.size(); ++i) {
        se += (T * est[i] - ref[i]).squaredNorm();
        worst = std::max(worst, (T * est[i] - ref[i]).norm());
      }
      // Its own closures at the base, against the reference (translation: the reference's yaw
      // between corrected scans is uncertain by degrees, see replay_from_raw).
      int own = 0, own_off = 0;
      double own_worst_m = 0;
      for (const base::LoopClosure& c : mapper.loop_closures()) {
        if (c.a.robot != RobotId(k) || c.b.robot != RobotId(k)) continue;
        const double off_m = closure_error(c, runs).translation_m;
        ++own;
        own_off += off_m > kMaxClosureErrorM;
        own_worst_m = std::max(own_worst_m, off_m);
      }
      std::printf(
          "[%s] robot %d refined own-frame ATE %.3f m (max %.3f); own closures %d, %d more than %.1f m off "
          "(worst %.2f m)\n",
          name, k, std::sqrt(se / est.size()), worst, own, own_off, kMaxClosureErrorM, own_worst_m);
    }
  }

  int inter = 0;
  double worst_m = 0, worst_rad = 0;
  for (const base::LoopClosure& c : mapper.loop_closures()) {
    if (c.a.robot == c.b.robot) continue;
    ++inter;
    const ClosureError e = closure_error(c, runs);
    worst_m = std::max(worst_m, e.translation_m);
    worst_rad = std::max(worst_rad, e.rotation_rad);
    EXPECT_LE(e.translation_m, kMaxClosureErrorM) << name << ": " << to_string(c.a) << " - " << to_string(c.b);
    EXPECT_LE(e.rotation_rad, kMaxClosureErrorRad) << name << ": " << to_string(c.a) << " - " << to_string(c.b);
  }
  int matched = 0;
  const double ate = merged_ate_m(runs, mapper, &matched);
  const base::LinkStats& ls = mapper.link_stats();
  std::printf(
      "[%s] %d robots: single-robot ATE %.3f m (%d kf), merged ATE %.3f m (%d kf), %d inter-robot "
      "closures (worst %.3f m / %.2f deg), links %d, refuted %d, deferred %d, linked-pair closures "
      "%d checked %d rejected %d, slowest optimize %.2f s\n",
      name, robots, single_ate, single_matched, ate, matched, inter, worst_m, worst_rad * 180 / M_PI, ls.linked,
      ls.rejected_map_contradiction, ls.deferred_spread, ls.linked_pair_closures, ls.linked_pair_checked,
      ls.linked_pair_rejected, stats.max_optimize_s);
  std::printf("[%s] deferred (inconclusive map check) %d\n", name, ls.deferred_inconclusive);
  ::testing::Test::RecordProperty("single_ate_m", std::to_string(single_ate));
  ::testing::Test::RecordProperty("merged_ate_m", std::to_string(ate));
  EXPECT_GT(inter, 0);
  EXPECT_LE(ate, 1.5 * single_ate) << name;
}

// The raw MIT CSAIL log split into 3 robots. All three link since the guided search around a link
// hypothesis whose rigid placement is refuted by a near miss (MapperOptions::guided_link): robots
// 1 and 2 each saw a corridor of the others' map 0.3-0.5 m off their rigid placement (their own
// drift), which refuted them (9.0 % and 6.0 % against the 6 % limit) until the check compared them
// as the guided closures place them (1.4 % and 4.9 %). Measured with CAIRN_MULTIROBOT_FUNNEL=1
// (2026-11-23): 24 inter-robot closures, worst 0.117 m / 1.5 deg; merged ATE 0.117 m against
// 0.090 m for the single robot.
ReplayLog mit_csail_replay() {
  const std::string raw_path = kData + "mit-csail/mit-csail.clf", ref_path = kData + "mit-csail/csail.corrected.log";
  if (!std::ifstream(raw_path) || !std::ifstream(ref_path)) return {};
  int matched = 0;
  ReplayLog log = replay_from_raw(read_carmen_log(raw_path), read_carmen_log(ref_path), &matched);
  EXPECT_GT(matched, 300);
  return log;
}

TEST(MultiRobotSplit, MitCsailRawInThreeRobots) {
  const ReplayLog log = mit_csail_replay();
  if (log.scans.empty()) GTEST_SKIP() << "data absent: " << kData << "mit-csail/ (mit-csail.clf, csail.corrected.log)";
  check_split(log, 3, "mit-csail");
}

TEST(MultiRobotSplit, IntelNoisyOdometryInFourRobots) {
  const std::string path = kData + "intel/intel.gfs.log";
  if (!std::ifstream(path)) GTEST_SKIP() << "data absent: " << path;
  check_split(replay_from_corrected(read_carmen_log(path), 7), 4, "intel");
}

// The same with the guided search around every link hypothesis (GuidedLinkOptions::on_every_link):
// every link then goes through it, and its residual gate is what keeps a wrong closure out (one
// 0.88 m off the reference, left 0.59 m off by the tentative placement; measured 2026-11-23: 133
// closures, worst 0.290 m, merged 0.085 m).
TEST(MultiRobotSplit, IntelWithTheGuidedSearchOnEveryLink) {
  const std::string path = kData + "intel/intel.gfs.log";
  if (!std::ifstream(path)) GTEST_SKIP() << "data absent: " << path;
  base::MapperOptions options;
  options.guided_link.on_every_link = true;
  check_split(replay_from_corrected(read_carmen_log(path), 7), 4, "intel-guided", options);
}

}  // namespace
}  // namespace cairn::multirobot
