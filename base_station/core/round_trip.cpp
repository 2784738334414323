#include "base_station/core/round_trip.h"

#include <algorithm>
#include <vector>

namespace cairn::base {

bool RoundTrip::add(uint64_t probe_ns, uint64_t held_ns, uint64_t arrival_ns) {
  if (probe_ns == 0 || probe_ns == last_probe_ns_ || probe_ns > arrival_ns) return false;
  const uint64_t away_ns = arrival_ns - probe_ns;
  if (held_ns > away_ns) return false;
  last_probe_ns_ = probe_ns;
  samples_ms_.push_back(double(away_ns - held_ns) * 1e-6);
  while (samples_ms_.size() > std::max<size_t>(options_.window, 1)) samples_ms_.pop_front();
  return true;
}

std::optional<double> RoundTrip::median_ms() const {
  if (samples_ms_.empty()) return std::nullopt;
  std::vector<double> s(samples_ms_.begin(), samples_ms_.end());
  const auto mid = s.begin() + std::ptrdiff_t(s.size() / 2);
  std::nth_element(s.begin(), mid, s.end());
  return *mid;
}

}  // namespace cairn::base
