#pragma once
// The console's search endpoint, apart from HTTP: the operator pauses and resumes the team's
// exploration and draws keep-out areas (base_station/core/search_controls.h).
//   POST /api/search {"action": "pause" | "resume" | "keep_out" | "clear_keep_out",
//                     "area_m": [x0, y0, x1, y1] (keep_out: two corners, map frame), "area": id (clear)}
//   GET  /api/search -> search_json()
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "base_station/core/search_controls.h"

namespace cairn::base {

/// Parses a request body; nullopt with `error` naming the fault (not JSON, unknown action, an area
/// that is not four numbers, a missing area id). Whether it applies now is SearchControls::check's.
std::optional<SearchControlRequest> parse_search_request(const std::string& body, std::string* error);

/// {"paused": bool, "stopped": [robot ids], "keep_out": [{"id", "min_m": [x, y], "max_m": [x, y]}]}
nlohmann::json search_json(const SearchControls& controls);

}  // namespace cairn::base
