#include "base_station/core/search_controls.h"

#include <gtest/gtest.h>

#include <limits>

namespace cairn::base {
namespace {

SearchControlRequest keep_out(double x0, double y0, double x1, double y1) {
  SearchControlRequest r;
  r.action = SearchAction::kKeepOut;
  r.corner_a_m = {x0, y0};
  r.corner_b_m = {x1, y1};
  return r;
}

TEST(SearchControls, PauseStopsTheNamedRobotsAndResumeHandsThemBack) {
  SearchControls c;
  EXPECT_EQ(*c.check({SearchAction::kResume}), "exploration is not paused");
  ASSERT_FALSE(c.check({SearchAction::kPause}));
  const SearchControlRecord pause = c.apply({SearchAction::kPause}, {RobotId(0), RobotId(2)}, 5);
  EXPECT_TRUE(c.paused());
  EXPECT_EQ(c.stopped_by_pause(), (std::vector<RobotId>{RobotId(0), RobotId(2)}));
  EXPECT_EQ(pause.seq, 1u);
  EXPECT_EQ(*c.check({SearchAction::kPause}), "exploration is already paused");
  c.apply({SearchAction::kResume}, {}, 9);
  EXPECT_FALSE(c.paused());
  EXPECT_TRUE(c.stopped_by_pause().empty());
}

TEST(SearchControls, KeepOutAreasAreOrderedCheckedAndRemovedById) {
  SearchControls c;
  ASSERT_FALSE(c.check(keep_out(4, 3, 2, 1)));
  const SearchControlRecord a = c.apply(keep_out(4, 3, 2, 1), {}, 1);  // corners in any order
  EXPECT_EQ(a.area.id, 1u);
  EXPECT_EQ(a.area.min_m, Eigen::Vector2d(2, 1));
  EXPECT_EQ(a.area.max_m, Eigen::Vector2d(4, 3));
  ASSERT_NE(c.area_containing({3, 2}), nullptr);
  EXPECT_EQ(c.area_containing({5, 2}), nullptr);
  c.apply(keep_out(10, 10, 12, 12), {}, 2);
  EXPECT_EQ(c.keep_out().size(), 2u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(*c.check(keep_out(nan, 0, 1, 1)), "the area's corners must be finite numbers");
  EXPECT_EQ(*c.check(keep_out(0, 0, 0.1, 5)), "the area is too narrow (0.10 m; at least 0.30 m a side)");
  EXPECT_EQ(*c.check(keep_out(0, 0, 1000, 5)), "the area is larger than 500 m a side");
  SearchControlRequest clear{SearchAction::kClearKeepOut};
  clear.area = 7;
  EXPECT_EQ(*c.check(clear), "there is no keep-out area 7");
  clear.area = 1;
  ASSERT_FALSE(c.check(clear));
  c.apply(clear, {}, 3);
  ASSERT_EQ(c.keep_out().size(), 1u);
  EXPECT_EQ(c.keep_out()[0].id, 2u);
  // A new area never reuses a removed area's id.
  EXPECT_EQ(c.apply(keep_out(0, 0, 1, 1), {}, 4).area.id, 3u);
}

TEST(SearchControls, NoMoreAreasThanOneMessageToARobotCarries) {
  SearchControlOptions options;
  options.max_areas = 2;
  SearchControls c(options);
  c.apply(keep_out(0, 0, 1, 1), {}, 1);
  c.apply(keep_out(2, 0, 3, 1), {}, 2);
  EXPECT_EQ(*c.check(keep_out(4, 0, 5, 1)), "there are already 2 keep-out areas: remove one first");
  EXPECT_EQ(SearchControlOptions().max_areas, 64u) << "cairn_msgs::KeepOutAreas holds 64";
}

TEST(SearchControls, JournalRecordsRebuildTheSameStateAndBadOnesAreNamed) {
  SearchControls live;
  std::vector<std::string> journal;
  journal.push_back(search_record_to_json(live.apply(keep_out(0, 0, 2, 2), {}, 1)));
  journal.push_back(search_record_to_json(live.apply({SearchAction::kPause}, {RobotId(1)}, 2)));
  SearchControls restored;
  for (const std::string& text : journal) {
    std::string error;
    const auto record = search_record_from_json(text, &error);
    ASSERT_TRUE(record) << error;
    ASSERT_TRUE(restored.restore(*record, &error)) << error;
  }
  EXPECT_TRUE(restored.paused());
  EXPECT_EQ(restored.stopped_by_pause(), std::vector<RobotId>{RobotId(1)});
  ASSERT_EQ(restored.keep_out().size(), 1u);
  EXPECT_EQ(restored.keep_out()[0].max_m, Eigen::Vector2d(2, 2));
  EXPECT_EQ(restored.last_seq(), 2u);
  std::string error;
  EXPECT_FALSE(search_record_from_json("{]", &error));
  EXPECT_EQ(error, "search control record: not a JSON object");
  EXPECT_FALSE(search_record_from_json(R"({"seq": 3, "action": 9, "area": 0, "at_ns": 0})", &error));
  EXPECT_EQ(error, "search control record: unknown \"action\"");
  // A record replayed twice (or out of order) does not apply again.
  const auto again = search_record_from_json(journal[0], &error);
  EXPECT_FALSE(restored.restore(*again, &error));
  EXPECT_EQ(error, "search control record 1 is not newer than 2");
}

}  // namespace
}  // namespace cairn::base
