#pragma once
// The control centre's alert log: every alert the base raised (keyed: "object:0-1",
// "contact:2", ...), when it was first and last raised (wall clock, for the team's own log), and
// whether an operator acknowledged it. An alert that is no longer raised stays in the log,
// inactive. Pure (the wall clock comes in); the base's thread owns it, acknowledgements arrive
// through the CommandInbox.
#include <map>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

namespace cairn::base {

class AlertLog {
 public:
  /// Notes the alerts raised now and returns them with "first_seen_s", "acked" (unacknowledged
  /// first, each group in the order given). An alert without a "key" is passed through, unlogged.
  nlohmann::json observe(const nlohmann::json& alerts, double wall_s, const std::set<std::string>& acked);
  /// Every alert ever raised, newest first: key, level, text, first_seen_s, last_seen_s, acked, active.
  nlohmann::json log() const;
  bool contains(const std::string& key) const { return entries_.count(key) > 0; }

 private:
  struct Entry {
    nlohmann::json alert;  ///< as last raised
    double first_seen_s = 0, last_seen_s = 0;
    bool acked = false, active = false;
  };
  std::map<std::string, Entry> entries_;
};

/// An operator's acknowledgement as the base journals it ({"key": "<alert key>"}), and back: nullopt
/// with `error` naming what is wrong (not JSON, no key, an empty or overlong key).
std::string alert_ack_to_json(const std::string& key);
std::optional<std::string> alert_ack_from_json(const std::string& text, std::string* error);

}  // namespace cairn::base
