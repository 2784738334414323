#include "base_station/console/search_api.h"

namespace cairn::base {

std::optional<SearchControlRequest> parse_search_request(const std::string& body, std::string* error) {
  auto fail = [error](const std::string& why) {
    *error = why;
    return std::nullopt;
  };
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return fail("the body is not JSON");
  if (!j.is_object()) return fail("the body must be a JSON object");
  if (!j.contains("action") || !j["action"].is_string())
    return fail("\"action\" is missing (pause, resume, keep_out, clear_keep_out)");
  const std::string action = j["action"];
  SearchControlRequest r;
  if (action == "pause") {
    r.action = SearchAction::kPause;
  } else if (action == "resume") {
    r.action = SearchAction::kResume;
  } else if (action == "keep_out") {
    r.action = SearchAction::kKeepOut;
    const nlohmann::json& a = j.contains("area_m") ? j["area_m"] : nlohmann::json();
    // JSON has no NaN: a non-finite corner arrives as null or a string and is named here.
    if (!a.is_array() || a.size() != 4 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number() ||
        !a[3].is_number())
      return fail("\"area_m\" must be four numbers [x0, y0, x1, y1] (metres, map frame) for keep_out");
    r.corner_a_m = {a[0].get<double>(), a[1].get<double>()};
    r.corner_b_m = {a[2].get<double>(), a[3].get<double>()};
  } else if (action == "clear_keep_out") {
    r.action = SearchAction::kClearKeepOut;
    if (!j.contains("area") || !j["area"].is_number_unsigned() || j["area"].get<uint64_t>() > 1000000)
      return fail("\"area\" must be a keep-out area's id for clear_keep_out");
    r.area = j["area"].get<uint32_t>();
  } else {
    return fail("unknown action \"" + action + "\" (pause, resume, keep_out, clear_keep_out)");
  }
  return r;
}

nlohmann::json search_json(const SearchControls& controls) {
  nlohmann::json areas = nlohmann::json::array();
  for (const KeepOutArea& a : controls.keep_out())
    areas.push_back({{"id", a.id}, {"min_m", {a.min_m.x(), a.min_m.y()}}, {"max_m", {a.max_m.x(), a.max_m.y()}}});
  std::vector<int> stopped;
  for (RobotId r : controls.stopped_by_pause()) stopped.push_back(r.value);
  return {{"paused", controls.paused()}, {"stopped", stopped}, {"keep_out", areas}};
}

}  // namespace cairn::base
