// Exploration strategies compared on whole missions (issue: robots that explore by themselves).
// Runs cairn_mission for every world x seed x strategy and prints, per world and strategy (means
// over the seeds): time to 50 / 90 / 99 % coverage of the explorable area, time until every victim
// was on the map, distance driven, collisions, goals blacklisted, final coverage, the worst robot's
// trajectory RMSE and objects found / precision. One coverage plot per world (first seed, one line
// per strategy). Strategies: scripted (the world's routes file, where it has one), nearest (every
// robot its own nearest frontier: explore_lite's behaviour), coordinated (the base's allocation),
// saliency (coordinated, frontiers near salient spots of the saliency layer first).
//   build/bin/bench_exploration_missions [--worlds office,collapsed] [--seeds 1,2,3]
//                                        [--strategies scripted,nearest,coordinated,saliency] [--out DIR]
//                                        [--report-only]   (the table again from the missions in DIR)
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "tools/mission/exploration_report.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

struct Mean {
  double sum = 0;
  int n = 0, never = 0;  ///< never: runs where the figure was not reached
  void add(const json& v) {
    if (v.is_number()) {
      sum += v.get<double>();
      ++n;
    } else {
      ++never;
    }
  }
  std::string text(int precision = 0) const {
    std::ostringstream s;
    s << std::fixed << std::setprecision(precision);
    if (n) s << sum / n;
    if (never) s << (n ? " (" : "") << "never x" << never << (n ? ")" : "");
    return s.str();
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Exploration strategies compared on whole simulated missions"};
  std::string worlds = "office,collapsed", seeds = "1,2,3", strategies = "scripted,nearest,coordinated,saliency";
  std::string out_dir = "out/bench_exploration";
  app.add_option("--worlds", worlds, "worlds/<name>.yaml, comma separated");
  app.add_option("--seeds", seeds, "simulator seeds, comma separated");
  app.add_option("--strategies", strategies, "scripted, nearest, coordinated, saliency");
  app.add_option("--out", out_dir, "where the missions and plots go");
  bool report_only = false;
  app.add_flag("--report-only", report_only, "print the table and plots from the missions already in --out");
  CLI11_PARSE(app, argc, argv);
  const fs::path bin = fs::canonical("/proc/self/exe").parent_path();
  const fs::path source(CAIRN_SOURCE_DIR);

  std::cout << "world        strategy     runs  t50_s     t90_s     t99_s     victims_s  driven_m  collisions  "
               "blacklisted  coverage  worst_rmse_m  objects  precision\n";
  int failures = 0;
  for (const std::string& world : split(worlds)) {
    std::vector<cairn::mission::CoverageLine> plot;
    int victims = 0;
    for (const std::string& strategy : split(strategies)) {
      const fs::path routes = source / "worlds" / "routes" / (world + ".yaml");
      if (strategy == "scripted" && !fs::exists(routes)) continue;  // a world made to be explored
      std::map<std::string, Mean> m;
      int runs = 0;
      for (const std::string& seed : split(seeds)) {
        const fs::path out = fs::path(out_dir) / world / (strategy + "_seed" + seed);
        if (!report_only) {
          fs::remove_all(out);
          fs::create_directories(out);
        }
        std::string cmd = (bin / "cairn_mission").string() + " --world " +
                          (source / "worlds" / (world + ".yaml")).string() + " --seed " + seed +
                          " --port 0 --timeout 3000 --out " + out.string();
        cmd += strategy == "scripted" ? " --routes " + routes.string() : " --exploration " + strategy;
        if (!report_only && std::system((cmd + " > " + (out / "mission.log").string() + " 2>&1").c_str()) != 0) {
          std::cerr << world << " " << strategy << " seed " << seed << ": mission failed, see " << (out / "mission.log")
                    << "\n";
          ++failures;
          continue;
        }
        std::ifstream in(out / "results.json");
        const json r = json::parse(in, nullptr, false);
        if (r.is_discarded()) {
          ++failures;
          continue;
        }
        ++runs;
        const json e = r.value("exploration", json::object()), ev = r.value("evaluation", json::object());
        m["t50"].add(e.value("t50_s", json()));
        m["t90"].add(e.value("t90_s", json()));
        m["t99"].add(e.value("t99_s", json()));
        m["victims"].add(e.value("all_victims_s", json()));
        m["driven"].add(e.value("distance_driven_m", json()));
        m["collisions"].add(e.value("collisions", json()));
        m["blacklisted"].add(e.value("goals_blacklisted", json()));
        m["coverage"].add(ev.value("coverage", json::object()).value("fraction", json()));
        double worst = 0;
        bool all_placed = true;
        for (const json& robot : ev.value("robots", json::array())) {
          all_placed = all_placed && robot.contains("ate_global_rmse_m");
          worst = std::max(worst, robot.value("ate_global_rmse_m", 0.0));
        }
        m["rmse"].add(all_placed ? json(worst) : json());  // "never": a robot was never placed
        m["objects"].add(ev.value("objects", json::object()).value("recall", json()));
        m["precision"].add(ev.value("objects", json::object()).value("precision", json()));
        for (const json& c : ev.value("classes", json::array())) {
          if (c.value("class", "") == "victim") victims = c.value("ground_truth", 0);
        }
        if (plot.empty() || plot.back().label != strategy) {  // the first seed's curve
          plot.push_back({strategy, e.value("coverage_per_second", json::array())});
        }
      }
      std::cout << std::left << std::setw(13) << world << std::setw(13) << strategy << std::setw(6) << runs
                << std::setw(10) << m["t50"].text() << std::setw(10) << m["t90"].text() << std::setw(10)
                << m["t99"].text() << std::setw(11) << m["victims"].text() << std::setw(10) << m["driven"].text()
                << std::setw(12) << m["collisions"].text(1) << std::setw(13) << m["blacklisted"].text(1)
                << std::setw(10) << m["coverage"].text(3) << std::setw(14) << m["rmse"].text(3) << std::setw(9)
                << m["objects"].text(2) << m["precision"].text(2) << std::endl;
    }
    const fs::path png = fs::path(out_dir) / ("coverage_" + world + ".png");
    if (!plot.empty() && !cairn::mission::write_coverage_plot(plot, victims, world, png.string())) {
      std::cerr << "cannot write " << png << "\n";
    }
  }
  std::cout << "plots: " << out_dir << "/coverage_<world>.png" << std::endl;
  return failures ? 1 : 0;
}
