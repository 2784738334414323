#include "tests/objects/objects_sim_eval.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

#include "common/trajectory.h"
#include "robot_agent/core/agent_pipeline.h"
#include "robot_agent/core/objects/object_detector.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace cairn::agent {
namespace {

struct Placed {
  std::string class_name;
  Eigen::Vector3d p;
  int weight;
};

std::vector<Placed> merge_reports(std::vector<Placed> in, double merge_m) {
  std::vector<Placed> out;
  for (const Placed& r : in) {
    bool merged = false;
    for (Placed& o : out) {
      if (o.class_name != r.class_name || (o.p - r.p).head<2>().norm() > merge_m) continue;
      o.p = (o.p * o.weight + r.p * r.weight) / double(o.weight + r.weight);
      o.weight += r.weight;
      merged = true;
      break;
    }
    if (!merged) out.push_back(r);
  }
  return out;
}

ClassScore score(const std::string& cls, const std::vector<sim::WorldObject>& truth, const std::vector<Placed>& found,
                 double match_m) {
  ClassScore s;
  s.class_name = cls;
  std::vector<bool> used(found.size(), false);
  for (const Placed& f : found) s.detected += (cls == "all" || f.class_name == cls);
  for (const sim::WorldObject& t : truth) {
    if (cls != "all" && t.object_class != cls) continue;
    ++s.ground_truth;
    int best = -1;
    double best_d = match_m;
    for (size_t i = 0; i < found.size(); ++i) {
      if (used[i] || found[i].class_name != t.object_class) continue;
      const double d = (found[i].p - t.center_m).head<2>().norm();
      if (d <= best_d) best_d = d, best = int(i);
    }
    if (best < 0) continue;
    used[size_t(best)] = true;
    ++s.matched;
    s.mean_error_xy_m += best_d;
    s.max_error_xy_m = std::max(s.max_error_xy_m, best_d);
    s.mean_error_xyz_m += (found[size_t(best)].p - t.center_m).norm();
  }
  if (s.matched) s.mean_error_xy_m /= s.matched, s.mean_error_xyz_m /= s.matched;
  return s;
}

sim::WorldFile load_world(const std::string& world_yaml, const SimEvalOptions& options) {
  sim::WorldLoadOptions load;
  load.routes_path = options.routes_yaml;
  return sim::load_world_file(world_yaml, load);
}

}  // namespace

std::string SimEvalResult::summary() const {
  std::ostringstream o;
  o.precision(3);
  for (const ClassScore& c : classes) {
    o << c.class_name << ": " << c.matched << "/" << c.ground_truth << " found, " << c.detected << " reported, recall "
      << c.recall() << " precision " << c.precision() << ", error " << c.mean_error_xy_m << " m xy mean ("
      << c.max_error_xy_m << " max, " << c.mean_error_xyz_m << " xyz)\n";
  }
  o << "placed by the true anchor pose (object pipeline alone):\n";
  for (const ClassScore& c : classes_true_anchor) {
    o << "  " << c.class_name << ": " << c.matched << "/" << c.ground_truth << " found, " << c.detected
      << " reported, error " << c.mean_error_xy_m << " m xy mean (" << c.max_error_xy_m << " max)\n";
  }
  o << frames << " RGB-D frames, " << reports << " reports, " << wall_ms_per_frame << " ms per frame\n";
  return o.str();
}

SimEvalResult evaluate_objects_in_world(const std::string& world_yaml, const SimEvalOptions& options) {
  const sim::WorldFile wf = load_world(world_yaml, options);
  sim::SimOptions so = wf.sim;
  if (options.max_sim_s > 0) so.duration_s = std::min(so.duration_s, options.max_sim_s);
  sim::Simulator sim(wf.world, so);
  std::map<int, std::unique_ptr<AgentPipeline>> agents;
  std::map<int, std::map<int32_t, SE2>> anchors;
  std::map<int, std::map<int32_t, StampNs>> anchor_stamps;
  std::map<ObjectId, ObjectReport> latest;
  for (RobotId id : sim.robot_ids()) agents.emplace(id.value, std::make_unique<AgentPipeline>(id, options.agent));
  SimEvalResult result;
  double wall_ms = 0.0;
  auto consume = [&](int robot, AgentOutputs out) {
    for (const Keyframe& k : out.keyframes)
      anchors[robot][k.id.seq] = k.T_local_base, anchor_stamps[robot][k.id.seq] = k.stamp_ns;
    for (ObjectReport& r : out.objects) latest[r.id] = std::move(r);
  };
  while (!sim.done()) {
    const sim::SimStep step = sim.step();
    for (const auto& o : step.odometry) agents.at(o.robot.value)->add_odometry(o.reading);
    for (const auto& s : step.scans) agents.at(s.robot.value)->add_scan(s.reading);
    for (const auto& f : step.frames) agents.at(f.robot.value)->add_rgbd(f.reading), ++result.frames;
    for (auto& [robot, agent] : agents) {
      const auto t0 = std::chrono::steady_clock::now();
      AgentOutputs out = agent->process(false);
      wall_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      consume(robot, std::move(out));
    }
  }
  for (auto& [robot, agent] : agents) consume(robot, agent->process(true));
  std::vector<Placed> placed, placed_true;
  for (const auto& [id, r] : latest) {
    const auto a = anchors[id.robot.value].find(r.anchor_seq);
    if (a == anchors[id.robot.value].end()) continue;
    const Eigen::Isometry3d T =
        sim.T_world_start(id.robot).to_isometry3() * a->second.to_isometry3() * r.T_anchor_object;
    placed.push_back({r.class_name, T.translation(), std::max(1, r.observations)});
    const auto truth = interpolate_pose(sim.ground_truth(id.robot), anchor_stamps[id.robot.value][r.anchor_seq]);
    if (truth)
      placed_true.push_back(
          {r.class_name, (truth->to_isometry3() * r.T_anchor_object).translation(), placed.back().weight});
    std::ostringstream line;
    line.precision(3);
    line << to_string(id) << " " << r.class_name << " at " << T.translation().transpose() << " obs " << r.observations
         << " conf " << r.confidence;
    result.placed.push_back(line.str());
  }
  result.reports = int(latest.size());
  const std::vector<Placed> merged = merge_reports(placed, options.merge_distance_m);
  const std::vector<Placed> merged_true = merge_reports(placed_true, options.merge_distance_m);
  std::vector<std::string> classes;
  for (const sim::WorldObject& o : wf.world.objects)
    if (std::find(classes.begin(), classes.end(), o.object_class) == classes.end()) classes.push_back(o.object_class);
  std::sort(classes.begin(), classes.end());
  classes.push_back("all");
  for (const std::string& c : classes) {
    result.classes.push_back(score(c, wf.world.objects, merged, options.match_distance_m));
    result.classes_true_anchor.push_back(score(c, wf.world.objects, merged_true, options.match_distance_m));
  }
  result.wall_ms_per_frame = result.frames ? wall_ms / result.frames : 0.0;
  return result;
}

std::vector<DetectionBias> diagnose_detections_in_world(const std::string& world_yaml, const SimEvalOptions& options) {
  const sim::WorldFile wf = load_world(world_yaml, options);
  sim::SimOptions so = wf.sim;
  if (options.max_sim_s > 0) so.duration_s = std::min(so.duration_s, options.max_sim_s);
  sim::Simulator sim(wf.world, so);
  const ObjectDetector detector(options.agent.detector);
  std::vector<DetectionBias> out(wf.world.objects.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const sim::WorldObject& o = wf.world.objects[i];
    out[i].object_id = o.id;
    out[i].class_name = o.object_class;
    out[i].shape = sim::to_string(o.shape);
  }
  while (!sim.done()) {
    const sim::SimStep step = sim.step();
    for (const auto& f : step.frames) {
      const Eigen::Isometry3d T = sim.ground_truth(f.robot).back().pose.to_isometry3();
      for (const Detection& d : detector.detect(f.reading)) {
        const Eigen::Vector3d p = T * d.centroid_base, cam = T * d.camera_base;
        int best = -1;
        double best_d = options.match_distance_m;
        for (size_t i = 0; i < out.size(); ++i) {
          const sim::WorldObject& o = wf.world.objects[i];
          const double dist = (p - o.center_m).head<2>().norm();
          if (o.object_class == d.class_name && dist < best_d) best_d = dist, best = int(i);
        }
        if (best < 0) continue;
        DetectionBias& b = out[size_t(best)];
        const Eigen::Vector3d c = wf.world.objects[size_t(best)].center_m;
        const Eigen::Vector2d ray = (c - cam).head<2>().normalized(), err = (p - c).head<2>();
        ++b.detections;
        char line[256];
        std::snprintf(
            line, sizeof line, "robot %d t %.1f s range %.2f m: along %+.3f across %+.3f m%s%s, %s %.2f x %.2f x %.2f",
            f.robot.value, double(f.reading.stamp_ns) * 1e-9, (c - cam).head<2>().norm(), err.dot(ray),
            ray.x() * err.y() - ray.y() * err.x(), d.truncated_side ? " truncated" : "", d.has_depth ? "" : " no-depth",
            to_string(d.shape.kind), d.shape.size_m.x(), d.shape.size_m.y(), d.shape.size_m.z());
        b.lines.push_back(line);
        b.truncated += d.truncated_side;
        b.without_depth += !d.has_depth;
        if (!d.has_depth) continue;  // the ground-homography fallback is scored by its line only
        b.mean_along_ray_m += err.dot(ray);
        b.mean_across_ray_m += ray.x() * err.y() - ray.y() * err.x();
        b.rms_xy_m += err.squaredNorm();
        b.mean_range_m += (c - cam).head<2>().norm();
      }
    }
  }
  for (DetectionBias& b : out) {
    const int n = b.detections - b.without_depth;
    if (n <= 0) continue;
    b.mean_along_ray_m /= n, b.mean_across_ray_m /= n, b.mean_range_m /= n;
    b.rms_xy_m = std::sqrt(b.rms_xy_m / n);
  }
  return out;
}

std::string format_bias(const std::vector<DetectionBias>& bias) {
  std::ostringstream o;
  o.precision(3);
  for (const DetectionBias& b : bias) {
    o << "  object " << b.object_id << " " << b.class_name << " " << b.shape << ": " << b.detections << " detections ("
      << b.truncated << " truncated, " << b.without_depth << " without depth), range " << b.mean_range_m
      << " m, bias along ray " << b.mean_along_ray_m << " m, across " << b.mean_across_ray_m << " m, rms xy "
      << b.rms_xy_m << " m\n";
  }
  return o.str();
}

}  // namespace cairn::agent
