#pragma once
// The demo's terminal side: progress lines from the base station's console API, and the final
// report (evaluation against ground truth + transport and process figures).
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "tools/mission/child_process.h"
#include "tools/mission/network_lab.h"
#include "tools/mission/ports.h"

namespace cairn::mission {

/// "[  12.3 s] ": how the mission's terminal lines start (seconds of wall time since the start).
std::string wall_stamp(double wall_s);

/// Polls http://<host>:<port>/api/status and /api/robots for one progress line.
class ProgressPoller {
 public:
  ProgressPoller(std::string host, int port, int robots) : host_(std::move(host)), port_(port), robots_(robots) {}
  std::string line(double wall_s) const;
  /// line(), or nothing when the mission's state (all but the wall time) is the same as in the
  /// last line returned: progress is printed only when something changed.
  std::optional<std::string> changed_line(double wall_s);

 private:
  std::string host_;
  int port_;
  int robots_;
  std::string last_state_;
};

/// Scores out/map against out/ground_truth, writes results.json and summary.txt into `out`,
/// prints the summary. Returns 0, or non-zero when results are missing or malformed.
/// `link`: the emulated radio's counters, when the mission ran behind one.
int report(const std::filesystem::path& out, double wall_s, const std::vector<std::unique_ptr<ChildProcess>>& procs,
           const std::optional<LinkTraffic>& link, std::ostream& os);

}  // namespace cairn::mission
