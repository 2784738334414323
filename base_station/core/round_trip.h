#pragma once
// The radio link's round trip to one robot, measured without synchronised clocks (as NTP does): the
// base stamps each ack with its own clock (the probe); the robot echoes the newest probe it received
// in its status, with how long it held it before writing that status; round trip = (the status's
// arrival - probe) - held. Arrivals are DDS's reception stamps, not when an app's loop got round to
// the sample: a base busy optimising is not a slow radio. Each probe counts once; the figure shown
// is the median of the newest few (one slow retransmission does not make the link look dead). Pure.
#include <cstdint>
#include <deque>
#include <optional>

namespace cairn::base {

struct RoundTripOptions {
  size_t window = 9;  ///< the median of this many newest probes
};

class RoundTrip {
 public:
  explicit RoundTrip(const RoundTripOptions& options = {}) : options_(options) {}

  /// One echo, all on the base's clock but `held_ns` (the robot's). False, and nothing kept, for no
  /// echo (probe 0), a probe already counted, or one that does not add up (from the base's future,
  /// or held longer than it was away: a clock that jumped, or an echo of a previous base's probe).
  bool add(uint64_t probe_ns, uint64_t held_ns, uint64_t arrival_ns);
  /// Median of the newest probes; nullopt before the first.
  std::optional<double> median_ms() const;

 private:
  RoundTripOptions options_;
  uint64_t last_probe_ns_ = 0;
  std::deque<double> samples_ms_;
};

}  // namespace cairn::base
