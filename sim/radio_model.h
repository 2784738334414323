#pragma once
// The simulated radio between each robot and the base station's antennas: the COST 231 multi-wall indoor
// propagation model (COST Action 231, "Digital mobile radio towards future generation systems",
// final report, 1999, section 4.7), in its simplest form. The power a robot receives is
//   P_rx = P_tx - L_1m - 10 n log10(d / 1 m) - L_wall * (walls crossed on the straight line),
// a wall being each run of wall cells of the floor plan that the line crosses (rubble counts as a
// wall; a wall's thickness does not add loss). The link is up while P_rx stays at or above the
// receiver's sensitivity and, once cut, comes back only after it has stayed at sensitivity +
// hysteresis for reconnect_s (a Wi-Fi association or an ad hoc mesh route takes seconds to come
// back), so a robot on the edge of coverage does not flap. Pure: no clock, no I/O.
// Defaults: 2.4 GHz Wi-Fi at 15 dBm; 40 dB at 1 m is free-space loss at 2.4 GHz; a 10 dB wall sits
// between COST 231's heavy wall (6.9 dB) and its concrete floor (18 dB): the walls of a collapsed
// building are concrete and rubble; -82 dBm is an 802.11 receiver's sensitivity at its lowest rate
// (IEEE 802.11-2016, table 17-18, 6 Mbit/s OFDM).
#include <Eigen/Core>
#include <vector>

#include "common/ids.h"
#include "common/time.h"
#include "sim/floor_plan.h"

namespace cairn::sim {

struct RadioOptions {
  std::vector<Eigen::Vector2d> antennas_m;  ///< world frame; the world loader puts one at each robot's start if none
  double tx_power_dbm = 15.0;
  double loss_at_1m_db = 40.0;
  double path_loss_exponent = 2.0;
  double wall_loss_db = 10.0;
  double sensitivity_dbm = -82.0;
  double hysteresis_db = 3.0;
  double reconnect_s = 2.0;
  double period_s = 0.5;  ///< how often the simulator re-evaluates each link (simulated time)
};

/// What the model says about one robot's link at one place.
struct RadioReading {
  double received_dbm = 0.0;
  int walls = 0;  ///< walls crossed towards the antenna heard best
};

/// Runs of wall cells the straight segment a-b crosses (sampled every half cell).
int walls_crossed(const FloorPlan& plan, const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m);

/// The model at `robot_m`: the antenna heard best (received_dbm -inf when there is none).
RadioReading radio_reading(const FloorPlan& plan, const RadioOptions& options, const Eigen::Vector2d& robot_m);

/// One link's state with hysteresis: starts up (the robots enter where the base is set up).
class RadioLink {
 public:
  explicit RadioLink(const RadioOptions& options) : options_(options) {}
  /// Takes a new reading at `now_ns`; returns true when the link's state changed.
  bool update(const RadioReading& reading, StampNs now_ns);
  bool up() const { return up_; }

 private:
  RadioOptions options_;
  bool up_ = true;
  StampNs in_range_since_ns_ = -1;  ///< while cut: since when the reading is good enough again
};

/// A link's reading, and whether its state changed with it.
struct RadioSample {
  RobotId robot;
  StampNs stamp_ns = 0;
  RadioReading reading;
  bool up = true;
  bool changed = false;
};

/// Every robot's link, re-evaluated every options.period_s of simulated time.
class RadioLinks {
 public:
  RadioLinks(const FloorPlan& plan, const RadioOptions& options) : plan_(plan), options_(options) {}
  /// The robots' true positions at `now_ns`: a sample per robot when the period is due, else none.
  std::vector<RadioSample> update(StampNs now_ns, const std::vector<std::pair<RobotId, Eigen::Vector2d>>& robots_m);

 private:
  const FloorPlan& plan_;
  RadioOptions options_;
  StampNs next_due_ns_ = 0;
  std::vector<std::pair<RobotId, RadioLink>> links_;
};

}  // namespace cairn::sim
