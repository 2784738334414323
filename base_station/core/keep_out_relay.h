#pragma once
// Which keep-out areas each robot must be told, and when: the operator draws areas on the merged map
// (SearchControls); a linked robot gets them turned into its own frame (KeepOutMessage), once per
// change of the areas, again when the base's estimate of where the robot's frame lies moved enough
// to matter, and again when the robot's status still reports an older version a while after a send
// (a sample lost on the radio). An unlinked robot gets nothing: nobody knows where its frame lies.
// Pure: states in, messages out; the app writes them and calls mark_sent.
#include <map>
#include <optional>
#include <vector>

#include "common/ids.h"
#include "common/keep_out.h"
#include "common/se2.h"

namespace cairn::base {

struct KeepOutRelayOptions {
  double resend_shift_m = 0.2;    ///< the robot's frame moved this far in the merged map: send again
  double resend_turn_rad = 0.02;  ///< or turned this much (0.2 m at 10 m)
  double unheld_resend_s = 5.0;   ///< the robot still reports an older version this long after a send
};

/// What the app knows of one robot when it asks.
struct KeepOutRobotState {
  RobotId robot{0};
  bool linked = false;
  SE2 T_global_local;                    ///< the robot's frame in the merged map (when linked)
  std::optional<uint32_t> held_version;  ///< the version the robot's newest status reports holding
};

class KeepOutRelay {
 public:
  explicit KeepOutRelay(const KeepOutRelayOptions& options = {}) : options_(options) {}

  /// The message to send `robot` now (its own frame, version one past the last sent, or the last
  /// again when it was lost), or nullopt when the robot holds what it should.
  std::optional<KeepOutMessage> due(const KeepOutRobotState& robot, const std::vector<KeepOutArea>& areas,
                                    double now_s) const;
  /// Records that `message` (from due) went out.
  void mark_sent(const KeepOutRobotState& robot, const std::vector<KeepOutArea>& areas, const KeepOutMessage& message,
                 double now_s);
  /// The newest version sent to `robot` (0: none).
  uint32_t sent_version(RobotId robot) const;

 private:
  struct Sent {
    uint32_t version = 0;
    SE2 T_global_local;
    std::vector<KeepOutArea> areas;
    double at_s = 0;
  };
  KeepOutRelayOptions options_;
  std::map<RobotId, Sent> sent_;
};

}  // namespace cairn::base
