#include "robot_agent/core/objects/jpda_tracker.h"

#include <gtest/gtest.h>

#include <random>

namespace cairn::agent {
namespace {

struct CrossingScenario {
  double speed_mps = 1.0;
  double half_angle_rad = 0.12;   ///< each target's heading off the x axis
  double sigma_m = 0.25;          ///< measurement noise
  double clutter_per_scan = 4.0;  ///< Poisson mean, uniform over the area
  double p_detection = 0.9;
  double dt_s = 0.5;
  int steps = 40;  ///< they cross at the middle
};

// Returns true when both tracks end on their own target (within 1.5 m, nearer than the other).
bool identities_kept(Association assoc, const CrossingScenario& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, s.sigma_m);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double T = s.steps * s.dt_s, L = s.speed_mps * T;
  const double vy = s.speed_mps * std::sin(s.half_angle_rad), vx = s.speed_mps * std::cos(s.half_angle_rad);
  const double y0 = vy * T / 2;  // they cross at t = T/2
  auto truth = [&](int k, double t) { return Eigen::Vector2d(vx * t, k == 0 ? -y0 + vy * t : y0 - vy * t); };
  const double area_w = L + 4, area_h = 2 * y0 + 4, area = area_w * area_h;
  JpdaOptions o;
  o.dims = 2;
  o.constant_velocity = true;
  o.process_noise = 0.01;
  o.gate_chi2 = 9.2;
  o.p_detection = s.p_detection;
  o.clutter_density = s.clutter_per_scan / area;
  o.association = assoc;
  JpdaTracker tracker(o);
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * s.sigma_m * s.sigma_m;
  int ids[2];
  for (int k = 0; k < 2; ++k) {
    ids[k] = tracker.add(truth(k, 0.0), R, 0.01);
    JpdaTarget* t = const_cast<JpdaTarget*>(tracker.find(ids[k]));
    t->x.tail(2) = Eigen::Vector2d(vx, k == 0 ? vy : -vy);
  }
  std::poisson_distribution<int> n_clutter(s.clutter_per_scan);
  for (int step = 1; step <= s.steps; ++step) {
    const double t = step * s.dt_s;
    tracker.predict(s.dt_s);
    std::vector<Eigen::VectorXd> z;
    for (int k = 0; k < 2; ++k)
      if (u01(rng) < s.p_detection) z.push_back(truth(k, t) + Eigen::Vector2d(noise(rng), noise(rng)));
    for (int c = n_clutter(rng); c > 0; --c)
      z.push_back(Eigen::Vector2d(-2 + area_w * u01(rng), -y0 - 2 + area_h * u01(rng)));
    std::shuffle(z.begin(), z.end(), rng);
    tracker.update(z, std::vector<Eigen::MatrixXd>(z.size(), R));
  }
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d p = tracker.position(*tracker.find(ids[k]));
    const double own = (p - truth(k, T)).norm(), other = (p - truth(1 - k, T)).norm();
    if (!(own < 1.5 && own < other)) return false;
  }
  return true;
}

double kept_rate(Association assoc, const CrossingScenario& s, int trials) {
  int kept = 0;
  for (int i = 0; i < trials; ++i) kept += identities_kept(assoc, s, 1000u + unsigned(i));
  return double(kept) / trials;
}

TEST(JpdaTracker, CrossingTracksInClutterKeepIdentitiesWhereNearestNeighbourSwaps) {
  const CrossingScenario s;
  const int trials = 100;
  const double jpda = kept_rate(Association::kJpda, s, trials);
  const double nn = kept_rate(Association::kNearestNeighbour, s, trials);
  RecordProperty("jpda_identity_kept", std::to_string(jpda));
  RecordProperty("nn_identity_kept", std::to_string(nn));
  std::printf("identities kept over %d crossings: JPDA %.2f, nearest neighbour %.2f\n", trials, jpda, nn);
  EXPECT_GE(jpda, 0.9);
  EXPECT_LE(nn, jpda - 0.15);
}

TEST(JpdaTracker, SingleTargetWithoutClutterConverges) {
  JpdaOptions o;
  o.dims = 3;
  JpdaTracker tracker(o);
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() * 0.01;
  const int id = tracker.add(Eigen::Vector3d(1, 2, 0.5), R);
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0, 0.1);
  for (int i = 0; i < 50; ++i) {
    tracker.predict(0.5);
    const JpdaUpdate u = tracker.update({Eigen::Vector3d(1.2 + n(rng), 2 + n(rng), 0.5 + n(rng))}, {R});
    ASSERT_EQ(u.beta.size(), 1u);
    EXPECT_GT(u.beta[0][0], 0.5);
  }
  EXPECT_LT((tracker.position(*tracker.find(id)) - Eigen::Vector3d(1.2, 2, 0.5)).norm(), 0.08);
  // An update without measurements keeps the estimate.
  const JpdaUpdate none = tracker.update({}, {});
  EXPECT_DOUBLE_EQ(none.beta[0][0], 1.0);
}

}  // namespace
}  // namespace cairn::agent
