#pragma once
// The operator's hand on the team's search, beside the per-robot commands: pause and resume the
// autonomous exploration, and keep-out areas (rectangles on the merged map) that no goal may lie
// in and no planned path may cross. SearchControls checks each change, keeps the state, and turns
// it into journal records and back, so a restarted base keeps the same areas and the same pause.
// Pure: requests in, state and records out.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/keep_out.h"  // KeepOutArea
#include "common/time.h"

namespace cairn::base {

enum class SearchAction : uint8_t { kPause = 0, kResume = 1, kKeepOut = 2, kClearKeepOut = 3 };
const char* to_string(SearchAction a);

struct SearchControlRequest {
  SearchAction action = SearchAction::kPause;
  Eigen::Vector2d corner_a_m{0, 0};  ///< kKeepOut: two opposite corners, any order
  Eigen::Vector2d corner_b_m{0, 0};
  uint32_t area = 0;  ///< kClearKeepOut
};

/// One applied change, as journaled (key: seq).
struct SearchControlRecord {
  uint32_t seq = 0;  ///< 1, 2, ... over the mission
  SearchAction action = SearchAction::kPause;
  KeepOutArea area;              ///< kKeepOut: the area made; kClearKeepOut: its id
  std::vector<RobotId> stopped;  ///< kPause: the robots the pause stopped (resumed with it)
  StampNs at_ns = 0;
};

struct SearchControlOptions {
  double min_side_m = 0.3;    ///< a smaller area is a slip of the mouse
  double max_side_m = 500.0;  ///< a larger one is a typo, not a building
  size_t max_areas = 64;      ///< what one message to a robot carries (dds::kMaxKeepOutAreas)
};

class SearchControls {
 public:
  explicit SearchControls(const SearchControlOptions& options = {}) : options_(options) {}

  /// Why `request` cannot apply now (pause while paused, resume while running, an area that is not
  /// finite or too small or large, removing an area that does not exist); nullopt when it can.
  std::optional<std::string> check(const SearchControlRequest& request) const;
  /// Applies a checked request; `stopped`: the robots a pause stops. Returns the record to journal.
  SearchControlRecord apply(const SearchControlRequest& request, const std::vector<RobotId>& stopped, StampNs now_ns);
  /// A record read back from the journal (in seq order). False, with `error`, if it does not fit.
  bool restore(const SearchControlRecord& record, std::string* error);

  bool paused() const { return paused_; }
  /// The robots the current pause stopped (empty when running).
  const std::vector<RobotId>& stopped_by_pause() const { return stopped_; }
  const std::vector<KeepOutArea>& keep_out() const { return areas_; }
  /// The first keep-out area holding p, if any.
  const KeepOutArea* area_containing(const Eigen::Vector2d& p_m) const;
  uint32_t last_seq() const { return last_seq_; }

 private:
  SearchControlOptions options_;
  bool paused_ = false;
  std::vector<RobotId> stopped_;
  std::vector<KeepOutArea> areas_;
  uint32_t next_area_ = 1;
  uint32_t last_seq_ = 0;
};

/// A record as JSON (for the journal), and back: nullopt with `error` naming the fault.
std::string search_record_to_json(const SearchControlRecord& record);
std::optional<SearchControlRecord> search_record_from_json(const std::string& text, std::string* error);

}  // namespace cairn::base
