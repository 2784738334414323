#pragma once
// The radio link's round trip to one robot, measured without synchronised clocks (as NTP does): the
// base stamps each ack with its own monotonic clock (the probe); the robot echoes the newest probe
// it took in its status, with how long it held it before writing that status; when the status
// arrives, round trip = (arrival - probe) - held. Each probe counts once; the figure shown is the
// median of the newest few (one slow retransmission does not make the link look dead). Pure.
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
