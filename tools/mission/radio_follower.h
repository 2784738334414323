#pragma once
// The mission's side of the simulated radio: the simulator appends every robot's link to a CSV
// (cairn_sim --radio, sim/radio_model.h); the follower reads what is new each time it is polled and
// cuts or restores that robot's traffic on the emulated radio (NetworkLab::set_robot_cut), and the
// summary says afterwards how often and how long each robot was out of range.
#include <fstream>
#include <functional>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cairn::mission {

/// One line of the radio CSV (t_s,robot,received_dbm,walls,up).
struct RadioRow {
  double t_s = 0;
  int robot = -1;
  double dbm = 0;
  int walls = 0;
  bool up = true;
};
/// nullopt for the header or a damaged line.
std::optional<RadioRow> parse_radio_row(const std::string& line);

/// One robot's link over a mission, from the radio CSV.
struct RadioLinkSummary {
  int robot = -1;
  int cuts = 0;                 ///< times the link went down
  double out_of_range_s = 0.0;  ///< simulated seconds with the link down
  double lowest_dbm = 0.0;      ///< the weakest reading
  double first_cut_s = -1.0;    ///< simulated time of the first cut (< 0: never)
};

/// Per robot, ascending id, from a whole radio CSV (t_s,robot,received_dbm,walls,up). Malformed
/// lines are skipped and counted in `*malformed` when given.
std::vector<RadioLinkSummary> summarize_radio(std::istream& csv, int* malformed = nullptr);

class RadioFollower {
 public:
  /// Cuts (true) or restores (false) a robot's link; false with a reason when it could not.
  using SetCut = std::function<bool(int robot, bool cut, std::string* error)>;
  RadioFollower(std::string csv_path, SetCut set_cut) : path_(std::move(csv_path)), set_cut_(std::move(set_cut)) {}
  /// Reads the lines appended since the last poll and applies every change of state; returns one
  /// line per change for the terminal ("radio: robot 1 out of range at mission t=42.5 s (-85 dBm, 4 walls)").
  std::vector<std::string> poll();

 private:
  std::string path_;
  SetCut set_cut_;
  std::ifstream in_;
  std::string partial_;     ///< an incomplete last line, completed by the next read
  std::map<int, bool> up_;  ///< the state applied to each robot's link
};

}  // namespace cairn::mission
