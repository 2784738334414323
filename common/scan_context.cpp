#include "common/scan_context.h"

#include <algorithm>
#include <cmath>

#include "common/scan_codec.h"

namespace cairn {

std::vector<float> compute_scan_context(const std::vector<Eigen::Vector2f>& points, const ScanContextOptions& o) {
  if (points.empty() || o.num_rings <= 0 || o.num_sectors <= 0) return {};
  std::vector<float> counts(size_t(o.num_rings * o.num_sectors), 0.f);
  for (const Eigen::Vector2f& p : points) {
    const double r = p.norm();
    if (!(r < o.max_range_m) || r <= 0.0) continue;
    const int ring = std::min(o.num_rings - 1, int(r / o.max_range_m * o.num_rings));
    const double a = std::atan2(double(p.y()), double(p.x())) + M_PI;  // [0, 2 pi]
    const int sector = std::min(o.num_sectors - 1, int(a / (2.0 * M_PI) * o.num_sectors));
    counts[size_t(ring * o.num_sectors + sector)] += 1.f;
  }
  for (float& c : counts) c = std::log1p(c);
  return counts;
}

std::vector<float> compute_scan_context(const LaserScan& scan, const ScanContextOptions& options) {
  return compute_scan_context(scan_to_points(scan), options);
}

std::vector<float> compute_keyframe_scan_context(const Keyframe& kf, const std::vector<const Keyframe*>& recent,
                                                 const ScanContextOptions& options) {
  std::vector<Eigen::Vector2f> points;
  auto append = [&](const Keyframe& other) {
    const SE2 T = kf.T_local_base.between(other.T_local_base);
    for (const Eigen::Vector2f& p : scan_to_points(other.scan)) points.push_back((T * p.cast<double>()).cast<float>());
  };
  append(kf);
  std::vector<int32_t> used;  // each predecessor once
  for (const Keyframe* other : recent) {
    if (other == nullptr || other->id.robot != kf.id.robot) continue;
    const int32_t back = kf.id.seq - other->id.seq;
    if (back < 1 || back >= options.descriptor_keyframes) continue;
    if (std::find(used.begin(), used.end(), other->id.seq) != used.end()) continue;
    used.push_back(other->id.seq);
    append(*other);
  }
  return compute_scan_context(points, options);
}

bool scan_context_size_ok(const std::vector<float>& d, const ScanContextOptions& o) {
  return o.num_rings > 0 && o.num_sectors > 0 && d.size() == size_t(o.num_rings * o.num_sectors);
}

std::vector<float> scan_context_ring_key(const std::vector<float>& d, const ScanContextOptions& o) {
  std::vector<float> key(size_t(o.num_rings), 0.f);
  if (d.size() != size_t(o.num_rings * o.num_sectors)) return key;
  for (int r = 0; r < o.num_rings; ++r) {
    double sum = 0;
    for (int s = 0; s < o.num_sectors; ++s) sum += d[size_t(r * o.num_sectors + s)];
    key[size_t(r)] = float(sum / o.num_sectors);
  }
  return key;
}

ScanContextMatch scan_context_distance(const std::vector<float>& a, const std::vector<float>& b,
                                       const ScanContextOptions& o) {
  ScanContextMatch best;
  const int R = o.num_rings, S = o.num_sectors;
  if (a.size() != size_t(R * S) || b.size() != a.size()) return best;
  // Column norms once.
  std::vector<double> na(size_t(S), 0.0), nb(size_t(S), 0.0);
  for (int s = 0; s < S; ++s) {
    for (int r = 0; r < R; ++r) {
      na[size_t(s)] += double(a[size_t(r * S + s)]) * a[size_t(r * S + s)];
      nb[size_t(s)] += double(b[size_t(r * S + s)]) * b[size_t(r * S + s)];
    }
  }
  // A point at angle alpha in a is at alpha - yaw in b: column c of a matches column c - shift of b.
  const int min_common = std::max(3, S / 10);
  for (int shift = 0; shift < S; ++shift) {
    double sum = 0;
    int common = 0;
    for (int c = 0; c < S; ++c) {
      const int cb = ((c - shift) % S + S) % S;
      if (na[size_t(c)] <= 0 || nb[size_t(cb)] <= 0) continue;
      double dot = 0;
      for (int r = 0; r < R; ++r) dot += double(a[size_t(r * S + c)]) * b[size_t(r * S + cb)];
      sum += 1.0 - dot / std::sqrt(na[size_t(c)] * nb[size_t(cb)]);
      ++common;
    }
    if (common < min_common) continue;
    const double d = sum / common;
    if (!best.valid || d < best.distance) {
      best.valid = true;
      best.distance = d;
      best.shift_sectors = shift;
    }
  }
  const int signed_shift = best.shift_sectors > S / 2 ? best.shift_sectors - S : best.shift_sectors;
  best.yaw_rad = signed_shift * 2.0 * M_PI / S;
  return best;
}

}  // namespace cairn

namespace cairn {

std::vector<uint8_t> encode_scan_context(const std::vector<float>& descriptor) {
  if (descriptor.empty()) return {};
  std::vector<uint8_t> q(descriptor.size());
  for (size_t i = 0; i < descriptor.size(); ++i) {
    const float v = std::isfinite(descriptor[i]) ? descriptor[i] * 32.f : 0.f;
    q[i] = uint8_t(std::lround(std::clamp(v, 0.f, 255.f)));
  }
  return zstd_compress(q.data(), q.size(), 3);
}

std::optional<std::vector<float>> decode_scan_context(const std::vector<uint8_t>& bytes, std::string* error) {
  if (bytes.empty()) return std::vector<float>{};
  auto q = zstd_decompress(bytes, 1 << 16, error);
  if (!q) return std::nullopt;
  std::vector<float> out(q->size());
  for (size_t i = 0; i < q->size(); ++i) out[i] = (*q)[i] / 32.f;
  return out;
}

}  // namespace cairn
