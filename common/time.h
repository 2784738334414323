#pragma once
// Time is message time (nanoseconds since the mission epoch), never the wall clock.
#include <cstdint>

namespace cairn {
using StampNs = int64_t;
constexpr StampNs kNsPerSec = 1'000'000'000;
inline double ns_to_sec(StampNs t_ns) { return double(t_ns) * 1e-9; }
inline StampNs sec_to_ns(double t_s) { return StampNs(t_s * 1e9 + (t_s >= 0 ? 0.5 : -0.5)); }
}  // namespace cairn
