#pragma once
// The exploration part of a mission's results: the base's coverage series (summary.json) turned
// into coverage of the explorable area per mission second, the times to 50 / 90 / 99 %, the time
// every victim was found, and a plot (coverage.png: coverage and victims against mission time).
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace cairn::mission {

struct ExplorationFigures {
  nlohmann::json per_second = nlohmann::json::array();  ///< [{t_s, free_m2, coverage, victims}]
  double final_coverage = 0;                            ///< of the explorable area, from the base's live figure
  std::optional<double> t50_s, t90_s, t99_s;            ///< first mission second at that coverage
  std::optional<double> all_victims_s;                  ///< first mission second with every victim on the map
};

/// `series`: summary.json's coverage_series; `reachable_m2`: the explorable area (cairn_eval);
/// `victims`: how many victims the world holds. The live free area counts a wall's blurred edge
/// as free now and then, so coverage is capped at 1.
ExplorationFigures exploration_figures(const nlohmann::json& series, double reachable_m2, int victims, double end_s);

/// One mission's curve on a plot (a strategy, when benchmarked).
struct CoverageLine {
  std::string label;
  nlohmann::json per_second;  ///< ExplorationFigures::per_second
};

/// Draws coverage (%, solid) and victims found (thin steps, right axis) against mission time, one
/// colour per line, into a PNG; false on I/O failure.
bool write_coverage_plot(const std::vector<CoverageLine>& lines, int victims, const std::string& title,
                         const std::string& path);

}  // namespace cairn::mission
