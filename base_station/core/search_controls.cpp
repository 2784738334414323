#include "base_station/core/search_controls.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace cairn::base {

const char* to_string(SearchAction a) {
  switch (a) {
    case SearchAction::kPause:
      return "pause exploration";
    case SearchAction::kResume:
      return "resume exploration";
    case SearchAction::kKeepOut:
      return "keep-out area";
    case SearchAction::kClearKeepOut:
      return "remove keep-out area";
  }
  return "?";
}

std::optional<std::string> SearchControls::check(const SearchControlRequest& r) const {
  switch (r.action) {
    case SearchAction::kPause:
      if (paused_) return "exploration is already paused";
      return std::nullopt;
    case SearchAction::kResume:
      if (!paused_) return "exploration is not paused";
      return std::nullopt;
    case SearchAction::kKeepOut: {
      if (!r.corner_a_m.allFinite() || !r.corner_b_m.allFinite()) return "the area's corners must be finite numbers";
      if (areas_.size() >= options_.max_areas) {
        return "there are already " + std::to_string(options_.max_areas) + " keep-out areas: remove one first";
      }
      const Eigen::Vector2d side = (r.corner_a_m - r.corner_b_m).cwiseAbs();
      char why[96];
      if (side.minCoeff() < options_.min_side_m) {
        std::snprintf(why, sizeof(why), "the area is too narrow (%.2f m; at least %.2f m a side)", side.minCoeff(),
                      options_.min_side_m);
        return std::string(why);
      }
      if (side.maxCoeff() > options_.max_side_m) {
        std::snprintf(why, sizeof(why), "the area is larger than %.0f m a side", options_.max_side_m);
        return std::string(why);
      }
      return std::nullopt;
    }
    case SearchAction::kClearKeepOut:
      if (std::none_of(areas_.begin(), areas_.end(), [&](const KeepOutArea& a) { return a.id == r.area; }))
        return "there is no keep-out area " + std::to_string(r.area);
      return std::nullopt;
  }
  return "unknown action";
}

SearchControlRecord SearchControls::apply(const SearchControlRequest& r, const std::vector<RobotId>& stopped,
                                          StampNs now_ns) {
  SearchControlRecord record;
  record.seq = last_seq_ + 1;
  record.action = r.action;
  record.at_ns = now_ns;
  if (r.action == SearchAction::kPause) record.stopped = stopped;
  if (r.action == SearchAction::kKeepOut)
    record.area = {next_area_, r.corner_a_m.cwiseMin(r.corner_b_m), r.corner_a_m.cwiseMax(r.corner_b_m)};
  if (r.action == SearchAction::kClearKeepOut) record.area.id = r.area;
  std::string unused;
  restore(record, &unused);  // checked above: it fits
  return record;
}

bool SearchControls::restore(const SearchControlRecord& r, std::string* error) {
  if (r.seq <= last_seq_) {
    *error = "search control record " + std::to_string(r.seq) + " is not newer than " + std::to_string(last_seq_);
    return false;
  }
  switch (r.action) {
    case SearchAction::kPause:
      paused_ = true;
      stopped_ = r.stopped;
      break;
    case SearchAction::kResume:
      paused_ = false;
      stopped_.clear();
      break;
    case SearchAction::kKeepOut:
      if (!r.area.min_m.allFinite() || !r.area.max_m.allFinite() ||
          (r.area.min_m.array() > r.area.max_m.array()).any()) {
        *error = "search control record " + std::to_string(r.seq) + ": the area's corners are not finite and ordered";
        return false;
      }
      areas_.push_back(r.area);
      next_area_ = std::max(next_area_, r.area.id + 1);
      break;
    case SearchAction::kClearKeepOut:
      areas_.erase(
          std::remove_if(areas_.begin(), areas_.end(), [&](const KeepOutArea& a) { return a.id == r.area.id; }),
          areas_.end());
      break;
  }
  last_seq_ = r.seq;
  return true;
}

const KeepOutArea* SearchControls::area_containing(const Eigen::Vector2d& p_m) const {
  for (const KeepOutArea& a : areas_)
    if (a.contains(p_m)) return &a;
  return nullptr;
}

std::string search_record_to_json(const SearchControlRecord& r) {
  std::vector<int> stopped;
  for (RobotId robot : r.stopped) stopped.push_back(robot.value);
  return nlohmann::json{{"seq", r.seq},
                        {"action", int(r.action)},
                        {"action_name", to_string(r.action)},  // for a person reading the journal
                        {"area", r.area.id},
                        {"min_m", {r.area.min_m.x(), r.area.min_m.y()}},
                        {"max_m", {r.area.max_m.x(), r.area.max_m.y()}},
                        {"stopped", stopped},
                        {"at_ns", r.at_ns}}
      .dump();
}

std::optional<SearchControlRecord> search_record_from_json(const std::string& text, std::string* error) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  auto fail = [error](const std::string& why) {
    *error = "search control record: " + why;
    return std::nullopt;
  };
  if (!j.is_object()) return fail("not a JSON object");
  for (const char* key : {"seq", "action", "area", "at_ns"})
    if (!j.contains(key) || !j[key].is_number_integer() || j[key].get<int64_t>() < 0)
      return fail(std::string("\"") + key + "\" is missing or not a non-negative integer");
  if (j["action"].get<int64_t>() > int64_t(SearchAction::kClearKeepOut)) return fail("unknown \"action\"");
  auto point = [&](const char* key, Eigen::Vector2d* p) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 2 || !j[key][0].is_number() ||
        !j[key][1].is_number())
      return false;
    *p = {j[key][0].get<double>(), j[key][1].get<double>()};
    return true;
  };
  SearchControlRecord r;
  if (!point("min_m", &r.area.min_m) || !point("max_m", &r.area.max_m))
    return fail("\"min_m\" and \"max_m\" must be [x, y]");
  if (!j.contains("stopped") || !j["stopped"].is_array()) return fail("\"stopped\" must be a list of robot ids");
  for (const nlohmann::json& robot : j["stopped"]) {
    if (!robot.is_number_integer()) return fail("\"stopped\" must be a list of robot ids");
    r.stopped.push_back(RobotId(robot.get<int>()));
  }
  r.seq = j["seq"].get<uint32_t>();
  r.action = SearchAction(j["action"].get<int>());
  r.area.id = j["area"].get<uint32_t>();
  r.at_ns = j["at_ns"].get<StampNs>();
  return r;
}

}  // namespace cairn::base
