// cairn_g2o_opt: optimises a planar g2o pose graph (VERTEX_SE2/EDGE_SE2, or the multi-robot
// EDGE_SE3:QUAT graphs with robot-letter keys) and prints g2o's chi2 and SE-Sync's objective
// before and after, with the time of each stage. Edges-only files start from odometry.
// Landmarks (VERTEX_XY / EDGE_SE2_XY, e.g. cairn_base's graph.g2o with markers and objects) are
// read and checked but not optimised: their count is printed and --out leaves them out.
//   cairn_g2o_opt FILE [FILE...] [--no-lago] [--no-sesync-polish] [--out OUT.g2o]
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>

#include <fstream>
#include "base_station/core/keyframe_pose_graph.h"
#include "base_station/core/lago_initializer.h"
#include "common/errors.h"
#include "common/g2o_io.h"
#include "common/trajectory.h"

namespace {

using cairn::G2oGraph;
using cairn::G2oKey;
using cairn::SE2;
using cairn::base::KeyframePoseGraph;
using Clock = std::chrono::steady_clock;

cairn::KeyframeId to_id(G2oKey k) { return cairn::KeyframeId{cairn::RobotId(k.robot), int32_t(k.index)}; }

KeyframePoseGraph to_pose_graph(const G2oGraph& g, const std::map<G2oKey, SE2>& poses,
                                cairn::base::EdgeResidualType type) {
  cairn::base::KeyframePoseGraphOptions o;
  o.residual = type;
  o.loop_loss = {cairn::base::RobustLossType::kNone, 1.0};
  KeyframePoseGraph graph(o);
  for (const auto& [k, p] : poses) graph.add_node(to_id(k), p);
  for (const auto& e : g.edges) {
    graph.add_edge({to_id(e.from), to_id(e.to), e.T_from_to, e.information, cairn::base::EdgeKind::kOdometry});
  }
  return graph;
}

std::map<G2oKey, SE2> from_pose_graph(const KeyframePoseGraph& graph) {
  std::map<G2oKey, SE2> out;
  for (const auto& [id, p] : graph.estimates()) out[G2oKey{id.robot.value, id.seq}] = p;
  return out;
}

/// Ground truth `x y th` per line, line k = robot-0 vertex k (vertigo's *_nodes_groundTruth.dat).
void print_ate(const std::string& path, const std::map<G2oKey, SE2>& poses, const char* stage) {
  std::ifstream in(path);
  if (!in) throw cairn::InputError(path + ": cannot open");
  cairn::Trajectory ref, est;
  double x, y, th;
  for (int64_t k = 0; in >> x >> y >> th; ++k) {
    auto it = poses.find(G2oKey{0, k});
    if (it == poses.end()) continue;
    ref.push_back({(k + 1) * cairn::kNsPerSec, SE2(x, y, th)});
    est.push_back({(k + 1) * cairn::kNsPerSec, it->second});
  }
  const auto stats = cairn::trajectory_error(est, ref);
  if (stats)
    std::printf("%-16s ATE rmse %.4f m  mean %.4f m  max %.4f m over %d poses\n", stage, stats->ate_rmse_m,
                stats->ate_mean_m, stats->ate_max_m, stats->matched);
}

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

void print_stage(const char* stage, const G2oGraph& g, const std::map<G2oKey, SE2>& poses, double ms) {
  std::printf("%-16s chi2 %.6e  sesync %.6e  time_ms %.1f\n", stage, cairn::g2o_chi2(g, poses),
              cairn::sesync_objective(g, poses), ms);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Optimise a planar g2o pose graph with Ceres (LAGO initialisation)"};
  std::vector<std::string> files;
  std::string out_path, ground_truth;
  bool no_lago = false, no_polish = false;
  int iterations = 200;
  app.add_option("files", files, "g2o file(s); several files are merged (multi-robot k.g2o)")->required();
  app.add_option("--out", out_path, "write the optimised graph here");
  app.add_option("--ground-truth", ground_truth, "true poses `x y th` per line: print the ATE");
  app.add_flag("--no-lago", no_lago, "skip the LAGO initialisation (start from the file / odometry)");
  app.add_flag("--no-sesync-polish", no_polish, "skip the final solve on SE-Sync's objective");
  app.add_option("--iterations", iterations, "max Ceres iterations per solve");
  bool cholmod = false;
  app.add_flag("--cholmod", cholmod, "sparse Cholesky by SuiteSparse CHOLMOD instead of Eigen (keyframe_pose_graph.h)");
  CLI11_PARSE(app, argc, argv);
  try {
    G2oGraph g;
    for (const std::string& f : files) cairn::merge_g2o(cairn::read_g2o(f), &g);
    auto t0 = Clock::now();
    std::map<G2oKey, SE2> poses = cairn::initialize_from_odometry(g);
    std::printf("graph: %zu poses, %zu edges, %s\n", poses.size(), g.edges.size(),
                g.vertices.empty() ? "edges-only (initialised from odometry)" : "with vertices");
    if (!g.points.empty() || !g.point_edges.empty()) {
      std::printf("skipped %zu landmark points (VERTEX_XY) and %zu landmark edges (EDGE_SE2_XY): poses only\n",
                  g.points.size(), g.point_edges.size());
      g.points.clear();
      g.point_edges.clear();
    }
    print_stage("initial", g, poses, ms_since(t0));
    const auto t_total = Clock::now();
    KeyframePoseGraph graph = to_pose_graph(g, poses, cairn::base::EdgeResidualType::kRelativePose);
    if (!no_lago) {
      t0 = Clock::now();
      const auto lago = cairn::base::lago_initialize(graph);
      if (!lago) throw cairn::InputError("LAGO initialisation failed: singular system");
      graph.set_estimates(*lago);
      print_stage("lago", g, from_pose_graph(graph), ms_since(t0));
    }
    cairn::base::PoseGraphSolveOptions so;
    so.max_iterations = iterations;
    so.eigen_sparse = !cholmod;
    t0 = Clock::now();
    auto r = graph.solve(so);
    print_stage("ceres", g, from_pose_graph(graph), ms_since(t0));
    std::printf("  ceres: %d iterations, %s\n", r.iterations, r.reason.c_str());
    if (!no_polish) {
      t0 = Clock::now();
      KeyframePoseGraph polish = to_pose_graph(g, from_pose_graph(graph), cairn::base::EdgeResidualType::kSeSync);
      r = polish.solve(so);
      graph = polish;
      print_stage("sesync-polish", g, from_pose_graph(graph), ms_since(t0));
    }
    std::printf("total solve time_ms %.1f\n", ms_since(t_total));
    if (!ground_truth.empty()) {
      print_ate(ground_truth, poses, "initial");
      print_ate(ground_truth, from_pose_graph(graph), "optimised");
    }
    if (!out_path.empty() && !cairn::write_g2o(out_path, g, from_pose_graph(graph), g.robot_keys)) {
      std::fprintf(stderr, "cannot write %s\n", out_path.c_str());
      return 1;
    }
  } catch (const cairn::InputError& e) {  // bad input: exit 2, as every Cairn tool
    std::fprintf(stderr, "cairn_g2o_opt: %s\n", e.what());
    return 2;
  }
  return 0;
}
