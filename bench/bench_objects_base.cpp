// bench_objects_base: the base station's cost per object registration (duplicate merging,
// global_object.h): one candidate pair verified by RGB-ICP, and merging 20 reports of 10 objects.
#include <benchmark/benchmark.h>

#include <cmath>

#include "base_station/core/global_object.h"

namespace {

using namespace cairn;

ColoredCloud half_cylinder(double radius_m, double height_m, double view_rad) {
  ColoredCloud c;
  for (int k = 0; k < 40; ++k) {
    const double a = view_rad - M_PI / 2 + M_PI * k / 39.0;
    for (double z = -height_m / 2; z <= height_m / 2 + 1e-9; z += 0.02)
      c.push_back(ColoredPoint{float(radius_m * std::cos(a)), float(radius_m * std::sin(a)), float(z), 230, 120, 40});
  }
  return c;
}

ObjectReport report(ObjectId id, double view_rad) {
  ObjectReport r;
  r.id = id;
  r.class_name = "victim";
  r.observations = 5;
  r.size_m = Eigen::Vector3f(0.4f, 0.4f, 0.5f);
  r.cloud = half_cylinder(0.2, 0.5, view_rad);
  return r;
}

Eigen::Isometry3d at(double x, double y, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() << x, y, 0.25;
  return T;
}

void BM_BaseMergeCheck(benchmark::State& state) {
  const ObjectReport a = report({RobotId(0), 0}, M_PI), b = report({RobotId(1), 0}, -M_PI / 2);
  const base::PlacedObjectReport pa{&a, at(4, 3, 0)}, pb{&b, at(4.06, 2.96, 0.05)};
  base::MergeCheck c;
  for (auto _ : state) c = base::check_same_object(pa, pb, {});
  state.counters["accepted"] = c.accepted;
  state.counters["fitness"] = c.fitness;
  state.counters["points"] = double(a.cloud.size());
}
BENCHMARK(BM_BaseMergeCheck)->Unit(benchmark::kMillisecond);

void BM_BaseMergeTwentyReports(benchmark::State& state) {
  std::vector<ObjectReport> reports;
  for (int i = 0; i < 10; ++i) {
    reports.push_back(report({RobotId(0), i}, M_PI));
    reports.push_back(report({RobotId(1), i}, -M_PI / 2));
  }
  std::vector<base::PlacedObjectReport> placed;
  for (size_t i = 0; i < reports.size(); ++i)
    placed.push_back({&reports[i], at(1.0 * double(i / 2), 0.05 * double(i % 2), 0)});
  size_t objects = 0;
  for (auto _ : state) objects = base::merge_object_reports(placed, {}).size();
  state.counters["objects"] = double(objects);
}
BENCHMARK(BM_BaseMergeTwentyReports)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
