#include "base_station/console/alert_log.h"

#include <algorithm>
#include <vector>

namespace cairn::base {

nlohmann::json AlertLog::observe(const nlohmann::json& alerts, double wall_s, const std::set<std::string>& acked) {
  for (auto& [key, e] : entries_) e.active = false;
  nlohmann::json open = nlohmann::json::array(), done = nlohmann::json::array();
  for (const nlohmann::json& a : alerts) {
    if (!a.contains("key") || !a["key"].is_string()) {
      open.push_back(a);
      continue;
    }
    const std::string key = a["key"];
    auto [it, fresh] = entries_.try_emplace(key);
    Entry& e = it->second;
    if (fresh) e.first_seen_s = wall_s;
    e.alert = a;
    e.last_seen_s = wall_s;
    e.active = true;
    e.acked = e.acked || acked.count(key) > 0;
    nlohmann::json shown = a;
    shown["first_seen_s"] = e.first_seen_s;
    shown["acked"] = e.acked;
    (e.acked ? done : open).push_back(std::move(shown));
  }
  for (auto& a : done) open.push_back(std::move(a));
  // An alert acknowledged after it stopped being raised (a collision risk that passed) is
  // acknowledged in the log too.
  for (auto& [key, e] : entries_) e.acked = e.acked || acked.count(key) > 0;
  return open;
}

nlohmann::json AlertLog::log() const {
  std::vector<const std::pair<const std::string, Entry>*> order;
  for (const auto& entry : entries_) order.push_back(&entry);
  std::sort(order.begin(), order.end(),
            [](const auto* a, const auto* b) { return a->second.first_seen_s > b->second.first_seen_s; });
  nlohmann::json out = nlohmann::json::array();
  for (const auto* entry : order) {
    const Entry& e = entry->second;
    out.push_back({{"key", entry->first},
                   {"level", e.alert.value("level", "")},
                   {"text", e.alert.value("text", "")},
                   {"first_seen_s", e.first_seen_s},
                   {"last_seen_s", e.last_seen_s},
                   {"acked", e.acked},
                   {"active", e.active}});
  }
  return out;
}

std::string alert_ack_to_json(const std::string& key) { return nlohmann::json{{"key", key}}.dump(); }

std::optional<std::string> alert_ack_from_json(const std::string& text, std::string* error) {
  constexpr size_t kMaxKeyChars = 64;  // keys are short: "object:0-1", "contact:2"
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object()) {
    *error = "alert acknowledgement: not a JSON object";
    return std::nullopt;
  }
  if (!j.contains("key") || !j["key"].is_string()) {
    *error = "alert acknowledgement: no \"key\" string";
    return std::nullopt;
  }
  const std::string key = j["key"];
  if (key.empty() || key.size() > kMaxKeyChars) {
    *error = "alert acknowledgement: the key is empty or longer than " + std::to_string(kMaxKeyChars) + " characters";
    return std::nullopt;
  }
  return key;
}

}  // namespace cairn::base
