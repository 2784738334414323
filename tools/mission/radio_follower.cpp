#include "tools/mission/radio_follower.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

namespace cairn::mission {
std::optional<RadioRow> parse_radio_row(const std::string& line) {
  RadioRow r;
  int up = 0;
  char c1 = 0, c2 = 0, c3 = 0, c4 = 0;
  std::istringstream in(line);
  if (!(in >> r.t_s >> c1 >> r.robot >> c2 >> r.dbm >> c3 >> r.walls >> c4 >> up) || c1 != ',' || c2 != ',' ||
      c3 != ',' || c4 != ',' || !std::isfinite(r.t_s) || r.robot < 0 || (up != 0 && up != 1)) {
    return std::nullopt;  // the header, or a damaged line
  }
  r.up = up == 1;
  return r;
}

std::vector<RadioLinkSummary> summarize_radio(std::istream& csv, int* malformed) {
  std::map<int, RadioLinkSummary> by_robot;
  std::map<int, RadioRow> last;
  std::string line;
  bool header = true;
  while (std::getline(csv, line)) {
    const auto row = parse_radio_row(line);
    if (!row) {
      if (!header && malformed) ++*malformed;
      header = false;
      continue;
    }
    header = false;
    RadioLinkSummary& s = by_robot[row->robot];
    const auto previous = last.find(row->robot);
    if (previous == last.end()) {
      s.robot = row->robot;
      s.lowest_dbm = row->dbm;
    } else if (!previous->second.up) {
      s.out_of_range_s += std::max(0.0, row->t_s - previous->second.t_s);
    }
    if (!row->up && (previous == last.end() || previous->second.up)) {
      ++s.cuts;
      if (s.first_cut_s < 0) s.first_cut_s = row->t_s;
    }
    s.lowest_dbm = std::min(s.lowest_dbm, row->dbm);
    last[row->robot] = *row;
  }
  std::vector<RadioLinkSummary> out;
  for (const auto& [robot, s] : by_robot) out.push_back(s);
  return out;
}

std::vector<std::string> RadioFollower::poll() {
  std::vector<std::string> lines;
  if (!in_.is_open()) {
    in_.open(path_);
    if (!in_.is_open()) return lines;  // the simulator has not made it yet
  }
  in_.clear();  // past the end last time: read on from where it stopped
  std::string chunk;
  while (std::getline(in_, chunk)) {
    if (in_.eof()) {  // no newline yet: the simulator is still writing this line
      partial_ += chunk;
      break;
    }
    const std::string line = partial_ + chunk;
    partial_.clear();
    const auto row = parse_radio_row(line);
    if (!row) continue;
    const auto it = up_.find(row->robot);
    const bool was_up = it == up_.end() || it->second;
    if (row->up == was_up) continue;
    std::string error;
    std::ostringstream text;
    text << "radio: robot " << row->robot << (row->up ? " back in range" : " out of range")
         << " at mission t=" << std::fixed << std::setprecision(1) << row->t_s << " s (" << std::lround(row->dbm)
         << " dBm, " << row->walls << " walls)";
    if (set_cut_(row->robot, !row->up, &error)) {
      up_[row->robot] = row->up;
    } else {
      text << ": NOT APPLIED: " << error;
    }
    lines.push_back(text.str());
  }
  return lines;
}

}  // namespace cairn::mission
