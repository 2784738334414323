// ObjectTracker with objects of the same class closer than its merge distance: two upright victims
// 0.4 m apart (0.1 m between their surfaces) must stay two tracks, while one object seen from
// changing sides stays one.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "robot_agent/core/objects/object_tracker.h"

namespace cairn::agent {
namespace {

// A detection of an upright cylinder (radius r) at `centre_local` seen from a robot at T_local_base:
// its visible half as the cloud, the centre from the (noisy) cylinder fit.
Detection cylinder_detection(const Eigen::Vector2d& centre_local, double r, const SE2& T_local_base,
                             std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 0.02);
  const SE2 T_base_local = T_local_base.inverse();
  Detection d;
  d.class_name = "victim";
  d.camera_base = Eigen::Vector3d(0.1, 0.0, 0.5);
  const Eigen::Vector2d c_base = T_base_local * centre_local;
  const Eigen::Vector2d to_cam = (d.camera_base.head<2>() - c_base).normalized();
  for (int k = 0; k <= 20; ++k) {
    const double a = std::atan2(to_cam.y(), to_cam.x()) - M_PI / 2 + M_PI * k / 20.0;
    for (double z = 0.0; z <= 0.5; z += 0.05)
      d.cloud_base.push_back(ColoredPoint{float(c_base.x() + r * std::cos(a)), float(c_base.y() + r * std::sin(a)),
                                          float(z), 230, 40, 30});
  }
  d.centroid_base = Eigen::Vector3d(c_base.x() + noise(rng), c_base.y() + noise(rng), 0.25);
  d.surface_centroid_base = d.centroid_base;
  d.shape.kind = ShapeKind::kCylinder;
  d.shape.converged = true;
  d.shape.center_m = d.centroid_base;
  d.shape.size_m = Eigen::Vector3d(2 * r, 2 * r, 0.5);
  return d;
}

std::map<int32_t, Eigen::Vector3d> run(const std::vector<Eigen::Vector2d>& objects, double r, bool circle,
                                       const ObjectTrackerOptions& options = {}) {
  ObjectTracker tracker(RobotId(0), options);
  std::mt19937 rng(7);
  std::map<int32_t, Eigen::Vector3d> latest;
  const Anchor anchor{0, SE2()};
  for (int i = 0; i < 30; ++i) {
    // Either drive past at 2-3 m, or circle the objects at 2.5 m (seeing every side).
    const double a = circle ? 2.0 * M_PI * i / 30.0 : 0.0;
    const Eigen::Vector2d mid = objects.size() > 1 ? Eigen::Vector2d(0.5 * (objects[0] + objects[1])) : objects[0];
    const SE2 pose = circle ? SE2(mid.x() - 2.5 * std::cos(a), mid.y() - 2.5 * std::sin(a), a)
                            : SE2(-1.0 + 0.1 * i, mid.y() - 2.5, M_PI / 2);
    std::vector<Detection> dets;
    for (const Eigen::Vector2d& o : objects) dets.push_back(cylinder_detection(o, r, pose, rng));
    for (const ObjectReport& rep : tracker.update(StampNs(1 + i) * 500'000'000, dets, pose, anchor))
      latest[rep.id.seq] = rep.T_anchor_object.translation();
  }
  return latest;
}

TEST(ObjectTracker, TwoVictimsFortyCentimetresApartStayTwoTracks) {
  const std::vector<Eigen::Vector2d> truth{{0.0, 0.0}, {0.4, 0.0}};
  const auto reports = run(truth, 0.15, false);
  ASSERT_EQ(reports.size(), 2u);
  for (const Eigen::Vector2d& t : truth) {
    double best = 1e9;
    for (const auto& [seq, p] : reports) best = std::min(best, (p.head<2>() - t).norm());
    EXPECT_LT(best, 0.05) << "object at " << t.transpose();
  }
  // Without the extent test (margins so wide every footprint contains everything) the gap is back.
  ObjectTrackerOptions no_extent;
  no_extent.separation_margin_m = 100.0;
  EXPECT_EQ(run(truth, 0.15, false, no_extent).size(), 1u);
}

TEST(ObjectTracker, OneObjectSeenFromEverySideStaysOneTrack) { EXPECT_EQ(run({{2.0, 1.0}}, 0.25, true).size(), 1u); }

}  // namespace
}  // namespace cairn::agent
