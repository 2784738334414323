// Exploration planning (base_station/core/exploration.h) on a real merged map: ms per plan for
// 1-8 robots. The base plans every 2 s while the map changes (BaseNodeOptions::exploration_period_s),
// on its app thread.
// Usage: bench_exploration [map.pgm]   (default out/collapsed/map/map.pgm, written by the demo:
// scripts/demo.sh); the map's resolution and origin come from the .yaml beside it.
#include <benchmark/benchmark.h>

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "base_station/core/exploration.h"
#include "common/yaml_config.h"

namespace {

using cairn::OccupancyGrid;
using cairn::RobotId;

std::string g_map_path = "out/collapsed/map/map.pgm";

/// A map_server PGM (0 occupied, 254 free, 205 unknown) back into a log-odds grid.
bool load_map(const std::string& pgm_path, OccupancyGrid* grid, std::string* error) {
  std::string stem = pgm_path.substr(0, pgm_path.size() - 4);
  double resolution = 0.05;
  std::vector<double> origin{0, 0, 0};
  try {
    const auto yaml = cairn::YamlConfig::load(stem + ".yaml");
    resolution = yaml.require<double>("resolution");
    origin = yaml.node()["origin"].as<std::vector<double>>();
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
  std::ifstream in(pgm_path, std::ios::binary);
  std::string magic;
  int w = 0, h = 0, maxval = 0;
  auto skip_comments = [&] {
    in >> std::ws;
    while (in.peek() == '#') {
      std::string line;
      std::getline(in, line);
      in >> std::ws;
    }
  };
  in >> magic;
  skip_comments();
  in >> w;
  skip_comments();
  in >> h;
  skip_comments();
  in >> maxval;
  in.get();
  if (!in || magic != "P5" || w <= 0 || h <= 0) {
    *error = "not a binary PGM: " + pgm_path;
    return false;
  }
  std::vector<uint8_t> px(size_t(w) * h);
  in.read(reinterpret_cast<char*>(px.data()), std::streamsize(px.size()));
  cairn::OccupancyGridOptions o;
  o.resolution_m = resolution;
  *grid =
      OccupancyGrid(o, {origin[0], origin[1]}, {origin[0] + w * resolution - 1e-6, origin[1] + h * resolution - 1e-6});
  for (int row = 0; row < h; ++row) {  // PGM top row first
    for (int col = 0; col < w; ++col) {
      const uint8_t v = px[size_t(row) * w + col];
      if (v != 205) grid->update_cell(col, h - 1 - row, v < 100 ? 2.f : -2.f);
    }
  }
  return true;
}

void BM_PlanExploration(benchmark::State& state) {
  static OccupancyGrid grid;
  static std::string error;
  static const bool loaded = load_map(g_map_path, &grid, &error);
  if (!loaded) {
    state.SkipWithError(("map absent (run scripts/demo.sh first): " + error).c_str());
    return;
  }
  // Robots spread over free cells along the map's diagonal.
  std::map<RobotId, Eigen::Vector2d> robots;
  for (int i = 0; i < state.range(0); ++i) {
    for (double t = (i + 0.5) / state.range(0); t < 1.0; t += 0.01) {
      const Eigen::Vector2i c(int(t * grid.width()), int(t * grid.height()));
      if (grid.known(c.x(), c.y()) && grid.probability(c.x(), c.y()) < 0.25) {
        robots[RobotId(i)] = grid.cell_center_m(c.x(), c.y());
        break;
      }
    }
  }
  size_t frontiers = 0, goals = 0;
  for (auto _ : state) {
    const auto plan = cairn::base::plan_exploration(grid, robots, {});
    frontiers = plan.frontiers.size();
    goals = plan.goals.size();
  }
  state.counters["cells"] = double(grid.width()) * grid.height();
  state.counters["frontiers"] = double(frontiers);
  state.counters["goals"] = double(goals);
}
BENCHMARK(BM_PlanExploration)->Arg(1)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc > 1) g_map_path = argv[1];
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
