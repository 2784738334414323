// bench_objects: the object pipeline's cost and message size (see docs/objects.md).
//  - BM_DetectTrack/<w>: ms per RGB-D frame for detection + tracking, frames rendered by the sim
//    core in worlds/office.yaml while driving past the hazard cylinder (320x240 and 640x480).
//  - BM_RgbIcp*: time per object registration (a view onto a fused track cloud).
//  - BM_ObjectMessage: bytes per object message (cloud + thumbnail + header) and the cloud
//    compression ratio (15 B/point raw float xyz + rgb vs encode_cloud).
#include <benchmark/benchmark.h>

#include <random>

#include "common/cloud_codec.h"
#include "common/registration/rgb_icp.h"
#include "robot_agent/core/objects/object_detector.h"
#include "robot_agent/core/objects/object_tracker.h"
#include "sim/rgbd_renderer.h"
#include "sim/world.h"

namespace {

using namespace cairn;

std::vector<RgbdFrame> render_frames(int width, int height, int n) {
  const sim::WorldFile wf = sim::load_world_file(std::string(CAIRN_SOURCE_DIR) + "/worlds/office.yaml");
  sim::CameraOptions cam = wf.sim.camera;
  cam.width = width, cam.height = height;
  const sim::RgbdRenderer renderer(cam, wf.world.floor_plan, wf.world.wall_height_m, wf.world.objects);
  std::mt19937_64 rng(1);
  std::vector<RgbdFrame> frames;
  for (int i = 0; i < n; ++i)  // approach the hazard cylinder at (8.6, 1) from the west, then the sphere
    frames.push_back(renderer.render(SE2(5.0 + 0.1 * i, 1.3, -0.1), StampNs(i) * 500'000'000, rng));
  return frames;
}

void BM_DetectTrack(benchmark::State& state) {
  const int w = int(state.range(0)), h = w * 3 / 4;
  const std::vector<RgbdFrame> frames = render_frames(w, h, 20);
  agent::ObjectDetector detector;
  agent::ObjectTracker tracker(RobotId(0));
  size_t i = 0, detections = 0;
  for (auto _ : state) {
    const RgbdFrame& f = frames[i % frames.size()];
    const auto dets = detector.detect(f);
    detections += dets.size();
    benchmark::DoNotOptimize(tracker.update(f.stamp_ns + StampNs(i / frames.size()) * 20'000'000'000, dets,
                                            SE2(0.1 * double(i % frames.size()), 0, 0), agent::Anchor{0, SE2()}));
    ++i;
  }
  state.counters["detections_per_frame"] = double(detections) / double(i);
  state.counters["fps"] = benchmark::Counter(double(i), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectTrack)->Arg(320)->Arg(640)->Unit(benchmark::kMillisecond);

void BM_DetectOnly(benchmark::State& state) {
  const int w = int(state.range(0));
  const std::vector<RgbdFrame> frames = render_frames(w, w * 3 / 4, 20);
  agent::ObjectDetector detector;
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(detector.detect(frames[i++ % frames.size()]));
}
BENCHMARK(BM_DetectOnly)->Arg(320)->Arg(640)->Unit(benchmark::kMillisecond);

// Two views of the hazard cylinder (detections' clouds in the base frame, robot moved 0.3 m).
std::pair<ColoredCloud, ColoredCloud> two_views() {
  const auto frames = render_frames(640, 480, 20);
  agent::ObjectDetector detector;
  ColoredCloud a, b;
  for (const auto& d : detector.detect(frames[5]))
    if (d.class_name == "hazard") a = d.cloud_base;
  for (const auto& d : detector.detect(frames[8]))
    if (d.class_name == "hazard")
      for (ColoredPoint p : d.cloud_base) p.x += 0.3f, b.push_back(p);
  return {a, b};
}

void BM_RgbIcp(benchmark::State& state) {
  const auto [a, b] = two_views();
  registration::RgbIcpOptions o;
  o.use_features = state.range(0) != 0;
  o.voxel_m = 0.025;
  o.feature_radius_m = 0.1;
  o.max_correspondence_m = 0.08;
  registration::RgbIcpResult r;
  for (auto _ : state) r = registration::rgb_icp(b, a, Eigen::Isometry3d::Identity(), o);
  state.counters["points"] = double(a.size());
  state.counters["fitness"] = r.score;
  state.counters["ransac_iterations"] = r.ransac_iterations;
  state.counters["icp_iterations"] = r.iterations;
  state.counters["feature_matches"] = r.feature_matches;
}
BENCHMARK(BM_RgbIcp)->Arg(0)->Arg(1)->ArgNames({"features"})->Unit(benchmark::kMillisecond);

// The agent's per-view registration as ObjectTracker runs it (no features, 4 cm voxel, <= 15 steps).
void BM_RgbIcpAgentViewFusion(benchmark::State& state) {
  const auto [a, b] = two_views();
  registration::RgbIcpOptions o;
  o.use_features = false;
  o.voxel_m = 0.04;
  o.max_correspondence_m = 0.08;
  o.max_iterations = 15;
  o.delta_translation_m = o.delta_rotation_rad = 1e-3;
  registration::RgbIcpResult r;
  for (auto _ : state) r = registration::rgb_icp(b, a, Eigen::Isometry3d::Identity(), o);
  state.counters["fitness"] = r.score;
  state.counters["icp_iterations"] = r.iterations;
}
BENCHMARK(BM_RgbIcpAgentViewFusion)->Unit(benchmark::kMillisecond);

void BM_ObjectMessage(benchmark::State& state) {
  const auto frames = render_frames(320, 240, 20);
  agent::ObjectDetector detector;
  agent::ObjectTracker tracker(RobotId(0));
  std::vector<ObjectReport> reports;
  for (size_t i = 0; i < frames.size(); ++i) {
    auto r = tracker.update(frames[i].stamp_ns, detector.detect(frames[i]), SE2(0.1 * double(i), 0, 0),
                            agent::Anchor{0, SE2()});
    for (auto& x : r) reports.push_back(std::move(x));
  }
  if (reports.empty()) return state.SkipWithError("no object report");
  const ObjectReport& r = reports.back();
  std::vector<uint8_t> bytes;
  for (auto _ : state) bytes = encode_cloud(r.cloud);
  const double header = 4 + 4 + 16 + 4 + 8 + 4 + 7 * 8 + 36 * 8 + 4 + 12;  // ids, class, pose, covariance, ...
  state.counters["cloud_points"] = double(r.cloud.size());
  state.counters["cloud_bytes"] = double(bytes.size());
  state.counters["thumbnail_bytes"] = double(r.thumbnail_jpeg.size());
  state.counters["message_bytes"] = header + double(bytes.size() + r.thumbnail_jpeg.size());
  state.counters["compression_ratio"] = 15.0 * double(r.cloud.size()) / double(std::max<size_t>(1, bytes.size()));
}
BENCHMARK(BM_ObjectMessage)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
