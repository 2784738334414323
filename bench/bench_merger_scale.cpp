// Merger scale (issue 4: "time per incremental update against graph size, 10 robots up to 20,000
// keyframes; aim for at most 100 ms per update at 10,000 keyframes"). A team of 10 robots, each
// linked by a start hint; every keyframe is followed by MultiRobotMapper::optimize() (the base's
// incremental update). Two configurations:
//  - default: loop detection off, noise-free odometry along random walks (each within 40 m of its
//    start), a small synthetic scan (90 beams, 3 m);
//  - --loops: loop detection on (place recognition, verification, PCM/map checks, loop windows and
//    refinement solves), robots wander through a random building of 8 m rooms (doors, closed walls,
//    pillars) with noisy odometry and 360-beam scans ray-cast in it, so they revisit rooms and
//    close loops within and between robots.
// Like the console, the global map is re-rendered every 10 updates (--render-every N). Prints per 1,000-keyframe
// window: mean / max ms per update, mean / max ms per render, loop closures, closures into linked
// pairs map-checked / rejected so far, full refinement solves in the window, resident memory; then
// the refusals by kind, the position error against the true poses (live, and after idle updates
// converged the refinement) and the cost of rendering the whole map from scratch.
// Usage: bench_merger_scale [total_keyframes=20000] [--loops [--no-map-check]] [--render-every N=10]
//                           [--refine-every N=MapperOptions::refine_every_updates]
//                           [--refine-keyframes-per-update N=MapperOptions::refine_keyframes_per_update]
//                           [--map-check-radius M=MapConsistencyOptions::local_radius_m; 0: whole map]
//                           [--max-iterations N=MapperOptions::incremental_max_iterations]
//                           [--cholmod: the pose graph's sparse Cholesky by CHOLMOD, not Eigen]
//                           [--export-g2o FILE: the final graph, to time its solve with cairn_g2o_opt]
//                           [--agent-poses-every N: every N updates one robot (in turn) sends its
//                            agent's loop-closed keyframe poses (KeyframePoses: here its true local
//                            poses), whose chain edges the base re-measures in place; 0 = never]
// (--no-map-check: no map-consistency check of closures into linked pairs. That check compares
// only the keyframes near the closure (MapConsistencyOptions::local_radius_m); it used to render
// every linked keyframe per check, O(keyframes), and dominated the --loops run. --refine-every 1
// with --refine-keyframes-per-update 0: a full refinement solve on every update with new loop
// edges, the former behaviour.)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/export/exporter.h"
#include "bench/merger_scale_world.h"
#include "common/laser_scan.h"

namespace {

using cairn::Keyframe;
using cairn::KeyframeId;
using cairn::RobotId;
using cairn::SE2;

constexpr int kRobots = 10;
using cairn::bench::Building;
using cairn::bench::kRoomM;
using cairn::bench::kRoomsX;
using cairn::bench::kRoomsY;
using cairn::bench::make_building;
using cairn::bench::make_keyframe;
using cairn::bench::next_loop_keyframe;
using cairn::bench::Walker;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// CPU time of this process, ms (the machine may be shared: wall time alone would mislead).
double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

/// Resident memory of this process from /proc/self/status ("VmRSS" or "VmHWM"), MB.
double memory_mb(const char* key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(key, 0) == 0) return std::atof(line.c_str() + std::strlen(key) + 1) / 1024.0;
  }
  return 0.0;
}

struct Stat {
  double sum = 0, max = 0;
  int n = 0;
  void add(double v) {
    sum += v;
    max = std::max(max, v);
    ++n;
  }
  double mean() const { return n ? sum / n : 0.0; }
};

struct Window {
  Stat wall, cpu, render_wall, render_cpu;
  int full_solves = 0;
  Stat full_cpu, full_iterations;  ///< of the updates that ran a full solve
};

}  // namespace

int main(int argc, char** argv) {
  int total = 20000, render_every = 10, refine_every = cairn::base::MapperOptions{}.refine_every_updates;
  int refine_per = cairn::base::MapperOptions{}.refine_keyframes_per_update;
  double check_radius_m = cairn::base::MapperOptions{}.map_check.local_radius_m;
  bool loops = false, map_check = true;
  int max_iterations = cairn::base::MapperOptions{}.incremental_max_iterations;
  bool cholmod = false;    // PoseGraphSolveOptions::eigen_sparse off
  std::string export_g2o;  // the final graph, to time and vary its solve offline (cairn_g2o_opt)
  int agent_poses_every = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--loops") == 0) {
      loops = true;
    } else if (std::strcmp(argv[i], "--no-map-check") == 0) {
      map_check = false;
    } else if (std::strcmp(argv[i], "--refine-keyframes-per-update") == 0 && i + 1 < argc) {
      refine_per = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--map-check-radius") == 0 && i + 1 < argc) {
      check_radius_m = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--refine-every") == 0 && i + 1 < argc) {
      refine_every = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--render-every") == 0 && i + 1 < argc) {
      render_every = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--cholmod") == 0) {
      cholmod = true;
    } else if (std::strcmp(argv[i], "--max-iterations") == 0 && i + 1 < argc) {
      max_iterations = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--agent-poses-every") == 0 && i + 1 < argc) {
      agent_poses_every = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--export-g2o") == 0 && i + 1 < argc) {
      export_g2o = argv[++i];
    } else {
      total = std::atoi(argv[i]);
    }
  }
  if (total <= 0 || render_every <= 0 || refine_every <= 0 || refine_per < 0 || max_iterations <= 0 ||
      agent_poses_every < 0) {
    std::fprintf(stderr,
                 "usage: bench_merger_scale [total_keyframes > 0] [--loops [--no-map-check]] [--render-every N > 0] "
                 "[--refine-every N > 0] [--refine-keyframes-per-update N >= 0] [--map-check-radius M] "
                 "[--max-iterations N > 0] [--cholmod] [--export-g2o FILE] [--agent-poses-every N >= 0]\n");
    return 2;
  }
  constexpr int kWindow = 1000;
  cairn::base::MapperOptions options;
  options.detect_loops = loops;
  options.incremental_graph = true;  // the live graph + window solves (the default; mapper_options.h)
  options.check_map_consistency = map_check;
  options.refine_every_updates = refine_every;
  options.refine_keyframes_per_update = refine_per;
  options.incremental_max_iterations = max_iterations;
  options.solve.eigen_sparse = !cholmod;
  options.map_check.local_radius_m = check_radius_m;
  cairn::base::MultiRobotMapper mapper(options);
  std::mt19937 rng(42);
  std::normal_distribution<double> turn(0.0, 0.3);
  const Building building = make_building(&rng);
  std::vector<Walker> walkers(kRobots);
  std::vector<SE2> pose(kRobots);
  std::vector<std::vector<SE2>> truth(kRobots);        // true global pose of each keyframe, by seq
  std::vector<SE2> start(kRobots);                     // where each robot's local frame sits
  std::vector<std::vector<SE2>> agent_local(kRobots);  // what a loop-closing agent would send: true local poses
  for (int r = 0; r < kRobots; ++r) {
    if (loops) {
      Walker& w = walkers[size_t(r)];
      w.x = (r * 3) % kRoomsX;
      w.y = (r * 7) % kRoomsY;
      w.true_pose = SE2((w.x + 0.5) * kRoomM, (w.y + 0.5) * kRoomM, 0.0);
      start[size_t(r)] = w.true_pose;
      mapper.set_robot_start(RobotId(r), w.true_pose);
    } else {
      start[size_t(r)] = SE2(30.0 * r, 0, 0);
      mapper.set_robot_start(RobotId(r), start[size_t(r)]);
    }
  }
  std::printf(
      "%d robots, loop detection %s%s, map rendered every %d updates, loop refinement every max(%d, "
      "nodes / %d) updates\n",
      kRobots, loops ? "on" : "off", loops && !map_check ? " (no map check)" : "", render_every, refine_every,
      refine_per);
  std::printf("           update (wall ms)  update (cpu ms)   render (wall ms)  render (cpu ms)\n");
  std::printf(
      "keyframes    mean     max      mean     max      mean     max     mean     max  loops  checked  "
      "rejected  full  rss_mb  full: cpu ms mean, iterations mean / max\n");
  Window win;
  int closures = 0, rejected_inconclusive = 0, rejected_contradicted = 0;
  for (int k = 0; k < total; ++k) {
    const int r = k % kRobots;
    Keyframe kf;
    if (loops) {
      kf = next_loop_keyframe(building, &rng, RobotId(r), &walkers[size_t(r)]);
      truth[size_t(r)].push_back(walkers[size_t(r)].true_pose);
    } else {
      // A random walk that turns back towards its start beyond 40 m (a bounded site).
      const SE2& cur = pose[size_t(r)];
      double dyaw = turn(rng);
      if (cur.translation().norm() > 40.0) {
        const double home = std::atan2(-cur.y(), -cur.x());
        dyaw = 0.3 * cairn::normalize_angle(home - cur.yaw()) + 0.1 * turn(rng);
      }
      const SE2 next = cur * SE2(0.5, 0.0, dyaw);
      kf = make_keyframe(RobotId(r), walkers[size_t(r)].seq++, pose[size_t(r)], next);
      pose[size_t(r)] = next;
      truth[size_t(r)].push_back(start[size_t(r)] * next);  // global, like the --loops world's
    }
    agent_local[size_t(r)].push_back(start[size_t(r)].inverse() * truth[size_t(r)].back());
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_ms();
    if (agent_poses_every > 0 && (k + 1) % agent_poses_every == 0) {
      const int sender = ((k + 1) / agent_poses_every) % kRobots;
      cairn::KeyframePoses update{RobotId(sender), 0, {}};
      for (size_t s = 0; s < agent_local[size_t(sender)].size(); ++s) {
        update.poses.push_back({int32_t(s), agent_local[size_t(sender)][s]});
      }
      mapper.add_keyframe_poses(update);
    }
    mapper.add_keyframe(kf);
    const cairn::base::OptimizeResult result = mapper.optimize();
    closures = result.loop_closures;
    win.full_solves += result.full_solve;
    for (const cairn::base::LinkEvent& e : result.link_events) {
      if (e.accepted) continue;
      (e.inconclusive ? rejected_inconclusive : rejected_contradicted) += 1;
    }
    win.cpu.add(cpu_ms() - c0);
    win.wall.add(ms_since(t0));
    if (result.full_solve) {
      win.full_cpu.add(cpu_ms() - c0);
      win.full_iterations.add(result.solve.iterations);
    }
    if ((k + 1) % render_every == 0) {
      const auto t1 = std::chrono::steady_clock::now();
      const double c1 = cpu_ms();
      mapper.global_map();
      win.render_cpu.add(cpu_ms() - c1);
      win.render_wall.add(ms_since(t1));
    }
    if ((k + 1) % kWindow == 0) {
      const cairn::base::LinkStats& ls = mapper.link_stats();
      std::printf(
          "%9d %7.2f %7.1f   %7.2f %7.1f   %7.2f %7.1f  %7.2f %7.1f  %5d  %7d  %8d  %4d  %6.0f  %7.1f %5.1f %3.0f\n",
          k + 1, win.wall.mean(), win.wall.max, win.cpu.mean(), win.cpu.max, win.render_wall.mean(),
          win.render_wall.max, win.render_cpu.mean(), win.render_cpu.max, closures, ls.linked_pair_checked,
          ls.linked_pair_rejected, win.full_solves, memory_mb("VmRSS"), win.full_cpu.mean(), win.full_iterations.mean(),
          win.full_iterations.max);
      std::fflush(stdout);
      win = Window{};
    }
  }
  // Accuracy: RMS / max position error of every keyframe against the truth (the starts are the true
  // ones, so the global frame is the world's), live (as the last update left it) and refined (after
  // idle updates until the refinement converged).
  auto report_error = [&](const char* what) {
    double sum2 = 0, worst = 0;
    int n = 0;
    for (int r = 0; r < kRobots; ++r) {
      for (size_t s = 0; s < truth[size_t(r)].size(); ++s) {
        const auto g = mapper.global_pose(KeyframeId{RobotId(r), int32_t(s)});
        if (!g) continue;
        const double e = (g->translation() - truth[size_t(r)][s].translation()).norm();
        sum2 += e * e, worst = std::max(worst, e), ++n;
      }
    }
    std::printf("position error %s: rms %.3f m, max %.3f m over %d keyframes\n", what, n ? std::sqrt(sum2 / n) : 0.0,
                worst, n);
  };
  const int implausible = mapper.link_stats().linked_pair_implausible;
  std::printf(
      "closures refused: %d implausible for a linked pair (unchecked); by the map check %d inconclusive "
      "(too little overlap), %d contradicted\n",
      implausible, rejected_inconclusive, rejected_contradicted - implausible);
  int wrong = 0, inter = 0;  // accepted closures more than 0.3 m / 0.1 rad off the truth
  for (const cairn::base::LoopClosure& c : mapper.loop_closures()) {
    const SE2 E = truth[size_t(c.a.robot.value)][size_t(c.a.seq)]
                      .between(truth[size_t(c.b.robot.value)][size_t(c.b.seq)])
                      .between(c.T_a_b);
    wrong += E.translation().norm() > 0.3 || std::abs(E.yaw()) > 0.1;
    inter += c.a.robot != c.b.robot;
  }
  std::printf("accepted closures: %zu (%d inter-robot), %d of them more than 0.3 m / 0.1 rad off the truth\n",
              mapper.loop_closures().size(), inter, wrong);
  report_error("live");
  {
    const double c0 = cpu_ms();
    int idle = 0;
    for (; idle < 200 && mapper.refinement_pending(); ++idle) mapper.optimize();
    std::printf("%d idle updates to converge the refinement (%.0f ms cpu)\n", idle, cpu_ms() - c0);
  }
  report_error("refined");
  if (!export_g2o.empty()) {
    std::string error;
    if (!cairn::base::write_graph_g2o(mapper.graph(), export_g2o, &error))
      std::fprintf(stderr, "%s\n", error.c_str());
    else
      std::printf("graph written: %s\n", export_g2o.c_str());
  }
  std::fflush(stdout);
  // The whole map from scratch (what every render cost before incremental rendering).
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_ms();
  cairn::base::GlobalMapRenderer scratch(options.grid, options.map_render);
  for (const auto& [id, kf] : mapper.keyframes()) scratch.set_pose(kf, *mapper.global_pose(id));
  const double area = scratch.render().known_area_m2();
  const double tiled_ms = ms_since(t0), tiled_cpu_ms = cpu_ms() - c0;
  // A plain full render: one grid, every keyframe once in id order (the former global_map()).
  // Its grid grows 5 m at a time (a copy each time): skipped on large runs, it takes minutes.
  if (total > 5000) {
    std::printf(
        "global map of %d keyframes from scratch: tiled %.0f ms (cpu %.0f, %.0f m2); incremental map "
        "%.0f m2; peak rss %.0f MB\n",
        total, tiled_ms, tiled_cpu_ms, area, mapper.mapped_area_m2(), memory_mb("VmHWM"));
    return 0;
  }
  const auto t2 = std::chrono::steady_clock::now();
  const double c2 = cpu_ms();
  cairn::OccupancyGrid plain(options.grid);
  for (const auto& [id, kf] : mapper.keyframes()) {
    std::vector<Eigen::Vector2f> no_return;
    for (size_t i = 0; i < kf.scan.ranges_m.size(); ++i) {
      if (kf.scan.ranges_m[i] < kf.scan.range_max_m) continue;
      const float a = cairn::beam_angle_rad(kf.scan, i), c = float(std::min<double>(kf.scan.range_max_m, 10.0));
      no_return.emplace_back(c * std::cos(a), c * std::sin(a));
    }
    plain.insert_scan(*mapper.global_pose(id), cairn::scan_to_points(kf.scan), no_return);
  }
  const double plain_ms = ms_since(t2), plain_cpu_ms = cpu_ms() - c2;
  std::printf(
      "global map of %d keyframes from scratch: tiled %.0f ms (cpu %.0f, %.0f m2), plain full render "
      "%.0f ms (cpu %.0f, %.0f m2); incremental map %.0f m2; peak rss %.0f MB\n",
      total, tiled_ms, tiled_cpu_ms, area, plain_ms, plain_cpu_ms, plain.known_area_m2(), mapper.mapped_area_m2(),
      memory_mb("VmHWM"));
  return 0;
}
