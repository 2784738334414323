#pragma once
// Time is message time (nanoseconds since the mission epoch), never the wall clock.
#include <cstdint>

namespace cairn {
using StampNs = int64_t;
constexpr StampNs kNsPerSec = 1'000'000'000;
inline double ns_to_sec(StampNs t_ns) { return double(t_ns) * 1e-9; }
inline StampNs sec_to_ns(double t_s) { return StampNs(t_s * 1e9 + (t_s >= 0 ? 0.5 : -0.5)); }
/// The largest |time| in seconds a stamp may hold (nanoseconds in an int64 reach 9.22e9 s, ~292
/// years): readers of outside input refuse stamps beyond it, as sec_to_ns would overflow.
constexpr double kMaxStampSec = 9.0e9;
inline bool stamp_sec_in_range(double t_s) { return t_s >= -kMaxStampSec && t_s <= kMaxStampSec; }
}  // namespace cairn
