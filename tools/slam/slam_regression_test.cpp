// Real-data regression of the robot agent's 2D SLAM (local SLAM + loop closure) as cairn_slam runs
// it: raw MIT CSAIL against the GMapping-corrected reference (scans matched by ranges), and the
// ACES corrected log with seeded odometry noise (10 % of distance, 3 deg per metre) against its own
// poses, and the Intel corrected log with the same noise against its poses and the Kuemmerle et al.
// relations. The target is an ATE of 0.05 m; the bounds below are the regression guard at the
// accuracy measured when this was written (MIT 0.076 m, ACES 0.159 m, Intel 0.078 m and relations
// 0.019 m, see the README of tools/slam) with a margin, so a change that loses accuracy fails loudly.
// Each run must also leave a map as self-consistent at revisits as the reference's own
// (reference_checks.h): that check needs no reference accuracy, which at ~5 cm is the ATE's floor.
#include <gtest/gtest.h>

#include <fstream>

#include "tools/slam/reference_checks.h"
#include "tools/slam/slam_eval.h"
#include "tools/slam/slam_runner.h"

namespace cairn::slam {
namespace {

const std::string kData = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/";

double ate_m(const Trajectory& estimate, const Trajectory& reference) {
  const auto e = trajectory_error(sample_at(estimate, reference, kNsPerSec), reference);
  EXPECT_TRUE(e.has_value());
  return e ? e->ate_rmse_m : 1e9;
}

// The estimate's map must be as self-consistent at revisits as the reference's (reference_checks.h):
// the ATE against a GMapping reference cannot tell which of the two is off at the 0.05-0.1 m level,
// the scans can tell a doubled wall.
void expect_as_consistent_as_reference(const char* name, const CarmenLog& corrected, const Trajectory& reference,
                                       const std::vector<size_t>& scan_index, const Trajectory& estimate) {
  const ScanChecks c = scan_checks(corrected, reference, scan_index, sample_at(estimate, reference, kNsPerSec));
  std::cout << name << ": revisit consistency (mean distance to the other pass) reference " << c.reference.mean_nn_m
            << " m, estimate " << c.estimate.mean_nn_m << " m; forward motion / laser " << c.forward.ratio[0] << " / "
            << c.forward.ratio[1] << " over " << c.forward.pairs << " pairs; affine fit " << c.affine.rmse_m
            << " m, scales " << c.affine.scale_major << " / " << c.affine.scale_minor << "\n";
  EXPECT_GE(c.poses, 0.99 * double(reference.size()));
  EXPECT_GT(c.estimate.revisit_fraction, 0.5);
  EXPECT_LT(c.estimate.mean_nn_m, 1.05 * c.reference.mean_nn_m);
}

TEST(SlamRegression, MitCsailRawAgainstCorrectedReference) {
  const std::string raw_path = kData + "mit-csail/mit-csail.clf", ref_path = kData + "mit-csail/csail.corrected.log";
  if (!std::ifstream(raw_path)) GTEST_SKIP() << "data absent: " << raw_path;
  if (!std::ifstream(ref_path)) GTEST_SKIP() << "data absent: " << ref_path;
  const CarmenLog raw = read_carmen_log(raw_path), corrected = read_carmen_log(ref_path);
  int unmatched = -1;
  std::vector<size_t> scan_index;
  const Trajectory reference = reference_from_corrected(corrected, &raw, &unmatched, &scan_index);
  EXPECT_EQ(unmatched, 0);
  EXPECT_EQ(reference.size(), corrected.scans.size());
  const SlamRunResult r = run_slam(raw, false, SlamRunOptions{});
  EXPECT_EQ(r.stats.scans, 1988);
  EXPECT_GT(r.stats.loop_closures, 100);
  const double slam = ate_m(r.trajectory, reference), odometry = ate_m(r.odometry, reference);
  RecordProperty("ate_m", std::to_string(slam));
  std::cout << "MIT CSAIL raw: ATE " << slam << " m (odometry " << odometry << " m)\n";
  EXPECT_GT(odometry, 1.0);
  EXPECT_LT(slam, 0.085);  // 0.072 (issue #3, covariance-weighted constraints)
  expect_as_consistent_as_reference("MIT CSAIL raw", corrected, reference, scan_index, r.trajectory);  // 1.3 % more
}

TEST(SlamRegression, AcesCorrectedWithNoisyOdometry) {
  const std::string path = kData + "aces/aces-corrected.log.gz";
  if (!std::ifstream(path)) GTEST_SKIP() << "data absent: " << path;
  const CarmenLog log = read_carmen_log(path);
  const SlamRunResult r = run_slam(log, true, SlamRunOptions{});
  std::vector<size_t> scan_index;
  const Trajectory reference = reference_from_corrected(log, nullptr, nullptr, &scan_index);
  const double slam = ate_m(r.trajectory, reference), odometry = ate_m(r.odometry, reference);
  RecordProperty("ate_m", std::to_string(slam));
  std::cout << "ACES + noise: ATE " << slam << " m (odometry " << odometry << " m)\n";
  EXPECT_GT(odometry, 1.0);
  EXPECT_LT(slam, 0.16);  // 0.129; noise seeds 2 / 3: 0.187 / 0.192
  expect_as_consistent_as_reference("ACES + noise", log, reference, scan_index, r.trajectory);  // 1.8 % more
}

TEST(SlamRegression, IntelCorrectedWithNoisyOdometryAndRelations) {
  const std::string path = kData + "intel/intel.gfs.log", relations_path = kData + "intel/intel.relations";
  if (!std::ifstream(path)) GTEST_SKIP() << "data absent: " << path;
  if (!std::ifstream(relations_path)) GTEST_SKIP() << "data absent: " << relations_path;
  const CarmenLog log = read_carmen_log(path);
  const SlamRunResult r = run_slam(log, true, SlamRunOptions{});
  std::vector<size_t> scan_index;
  const Trajectory reference = reference_from_corrected(log, nullptr, nullptr, &scan_index);
  const double slam = ate_m(r.trajectory, reference), odometry = ate_m(r.odometry, reference);
  const auto relations = read_relations(relations_path);
  const RelationsError rel = relations_error(relations, r.trajectory, estimate_time_offset_s(relations, r.trajectory));
  RecordProperty("ate_m", std::to_string(slam));
  RecordProperty("relations_trans_mean_m", std::to_string(rel.trans_mean_m));
  std::cout << "Intel + noise: ATE " << slam << " m (odometry " << odometry << " m), relations " << rel.trans_mean_m
            << " +- " << rel.trans_sd_m << " m over " << rel.used << "\n";
  EXPECT_GT(odometry, 1.0);
  EXPECT_LT(slam, 0.09);  // 0.073
  EXPECT_GE(rel.used, 40);
  EXPECT_LT(rel.trans_mean_m, 0.03);
  EXPECT_LT(rel.rot_mean_deg, 0.6);
  expect_as_consistent_as_reference("Intel + noise", log, reference, scan_index, r.trajectory);  // 0.5 % less
}

// The likelihood field joined along sparsely sampled walls (range_data_inserter.h
// field_line_max_gap_m = 0.6, off by default: MIT drops to 0.11 m against its reference, see the
// README of tools/slam) on the two logs with 1-degree scans, several noise seeds each.
TEST(SlamRegression, FieldLinesOnSparseScans) {
  const std::string aces_path = kData + "aces/aces-corrected.log.gz", intel_path = kData + "intel/intel.gfs.log";
  if (!std::ifstream(aces_path)) GTEST_SKIP() << "data absent: " << aces_path;
  if (!std::ifstream(intel_path)) GTEST_SKIP() << "data absent: " << intel_path;
  SlamRunOptions options;
  options.slam.submaps.inserter.field_line_max_gap_m = 0.6;
  for (const auto& [path, bound_m] : {std::pair<std::string, double>{aces_path, 0.12}, {intel_path, 0.075}}) {
    const CarmenLog log = read_carmen_log(path);
    const Trajectory reference = reference_from_corrected(log);
    for (uint32_t seed : {1u, 2u}) {
      options.noise.seed = seed;
      const double slam = ate_m(run_slam(log, true, options).trajectory, reference);
      std::cout << path << " seed " << seed << " + field lines: ATE " << slam << " m\n";
      EXPECT_LT(slam, bound_m);  // ACES 0.074 / 0.098 (defaults 0.129 / 0.187); Intel 0.063 / 0.064 (0.073 / 0.072)
    }
  }
}

}  // namespace
}  // namespace cairn::slam
