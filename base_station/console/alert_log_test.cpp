#include "base_station/console/alert_log.h"

#include <gtest/gtest.h>

namespace cairn::base {
namespace {

nlohmann::json alert(const std::string& key, const std::string& text) {
  return {{"key", key}, {"level", "critical"}, {"text", text}};
}

TEST(AlertLog, KeepsFirstSeenAcknowledgementAndAlertsNoLongerRaised) {
  AlertLog log;
  auto shown = log.observe(nlohmann::json::array({alert("object:0-1", "Victim found"),
                                                  alert("contact:2", "Robot 2 out of contact for 12 s")}),
                           1000.0, {});
  ASSERT_EQ(shown.size(), 2u);
  EXPECT_EQ(shown[0]["first_seen_s"], 1000.0);
  EXPECT_FALSE(shown[0]["acked"].get<bool>());
  // Acknowledged: it goes after the open ones; the contact alert's text moves on, its first sight stays.
  shown = log.observe(nlohmann::json::array(
                          {alert("object:0-1", "Victim found"), alert("contact:2", "Robot 2 out of contact for 14 s")}),
                      1002.0, {"object:0-1"});
  EXPECT_EQ(shown[0]["key"], "contact:2");
  EXPECT_EQ(shown[0]["first_seen_s"], 1000.0);
  EXPECT_EQ(shown[1]["key"], "object:0-1");
  EXPECT_TRUE(shown[1]["acked"].get<bool>());
  // Contact is back: the alert is no longer raised, but it stays in the log.
  shown = log.observe(nlohmann::json::array({alert("object:0-1", "Victim found")}), 1005.0, {});
  EXPECT_EQ(shown.size(), 1u);
  EXPECT_TRUE(shown[0]["acked"].get<bool>()) << "an acknowledgement is kept";
  const auto entries = log.log();
  ASSERT_EQ(entries.size(), 2u);
  for (const auto& e : entries) {
    if (e["key"] == "contact:2") {
      EXPECT_FALSE(e["active"].get<bool>());
      EXPECT_EQ(e["text"], "Robot 2 out of contact for 14 s");
      EXPECT_EQ(e["last_seen_s"], 1002.0);
    }
  }
  EXPECT_TRUE(log.contains("contact:2"));
  EXPECT_FALSE(log.contains("stuck:2"));
  // Acknowledged after it stopped being raised: the log says so.
  log.observe(nlohmann::json::array({alert("object:0-1", "Victim found")}), 1006.0, {"contact:2"});
  for (const auto& e : log.log()) EXPECT_TRUE(e["acked"].get<bool>()) << e.dump();
}

TEST(AlertLog, AnAcknowledgementRoundTripsThroughTheJournalAndADamagedOneIsNamed) {
  std::string error;
  EXPECT_EQ(alert_ack_from_json(alert_ack_to_json("object:0-1"), &error).value_or(error), "object:0-1");
  EXPECT_FALSE(alert_ack_from_json("{\"key\": ", &error));
  EXPECT_EQ(error, "alert acknowledgement: not a JSON object");
  EXPECT_FALSE(alert_ack_from_json(R"({"key": 7})", &error));
  EXPECT_EQ(error, "alert acknowledgement: no \"key\" string");
  EXPECT_FALSE(alert_ack_from_json(R"({"key": ""})", &error));
  EXPECT_EQ(error, "alert acknowledgement: the key is empty or longer than 64 characters");
}

}  // namespace
}  // namespace cairn::base
