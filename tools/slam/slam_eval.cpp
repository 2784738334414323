#include "tools/slam/slam_eval.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <unordered_map>

#include "common/errors.h"

namespace cairn::slam {
namespace {

// Ranges rounded to centimetres: identical scans from two logs (different print precision) agree.
std::string range_key(const LaserScan& s) {
  std::string key;
  key.reserve(s.ranges_m.size() * 3);
  for (float r : s.ranges_m) key += std::to_string(std::isfinite(r) ? std::lround(r * 100.f) : -1) + ",";
  return key;
}

double mean_sd(const std::vector<double>& v, double* sd) {
  if (v.empty()) return *sd = 0.0;
  double m = 0;
  for (double x : v) m += x;
  m /= double(v.size());
  double ss = 0;
  for (double x : v) ss += (x - m) * (x - m);
  *sd = v.size() > 1 ? std::sqrt(ss / double(v.size() - 1)) : 0.0;
  return m;
}

}  // namespace

Trajectory reference_from_corrected(const CarmenLog& corrected, const CarmenLog* raw, int* unmatched,
                                    std::vector<size_t>* scan_index) {
  Trajectory ref;
  int missing = 0;
  if (scan_index) scan_index->clear();
  if (!raw) {
    for (size_t i = 0; i < corrected.scans.size(); ++i) {
      ref.push_back({corrected.scans[i].stamp_ns, corrected.scans[i].T_world_laser});
      if (scan_index) scan_index->push_back(i);
    }
  } else {
    std::unordered_multimap<std::string, size_t> raw_by_key;
    for (size_t i = 0; i < raw->scans.size(); ++i) raw_by_key.emplace(range_key(raw->scans[i].scan), i);
    size_t next_raw = 0;  // scans appear in the same order: take the first twin not before the last match
    for (size_t i = 0; i < corrected.scans.size(); ++i) {
      const CarmenScan& s = corrected.scans[i];
      auto [lo, hi] = raw_by_key.equal_range(range_key(s.scan));
      std::optional<size_t> best;
      for (auto it = lo; it != hi; ++it) {
        if (it->second >= next_raw && (!best || it->second < *best)) best = it->second;
      }
      if (!best) {
        ++missing;
        continue;
      }
      next_raw = *best + 1;
      ref.push_back({raw->scans[*best].stamp_ns, s.T_world_laser});
      if (scan_index) scan_index->push_back(i);
    }
  }
  if (unmatched) *unmatched = missing;
  return ref;
}

Trajectory sample_at(const Trajectory& estimate, const Trajectory& reference, StampNs max_gap_ns) {
  Trajectory out;
  for (const auto& r : reference) {
    if (auto p = interpolate_pose(estimate, r.stamp_ns, max_gap_ns)) out.push_back({r.stamp_ns, *p});
  }
  return out;
}

std::vector<Relation> read_relations(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open relations file");
  std::vector<Relation> out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double t1, t2, x, y, z, roll, pitch, yaw;
    if (!(ss >> t1 >> t2 >> x >> y >> z >> roll >> pitch >> yaw) || !std::isfinite(x + y + yaw + t1 + t2) ||
        !stamp_sec_in_range(t1) || !stamp_sec_in_range(t2)) {
      throw InputError(path + ":" + std::to_string(line_no) +
                       ": expected 't1 t2 x y z roll pitch yaw' (finite; times within +-9e9 s)");
    }
    out.push_back({t1, t2, SE2(x, y, yaw)});
  }
  return out;
}

double estimate_time_offset_s(const std::vector<Relation>& relations, const Trajectory& estimate) {
  // Candidates: the most frequent (relation t1 - estimate stamp) differences; the winner is the one
  // under which most relations have both ends on estimate stamps.
  std::unordered_map<long long, int> votes;
  for (const Relation& r : relations) {
    for (const auto& p : estimate) votes[std::llround((r.t1_s - ns_to_sec(p.stamp_ns)) * 1000.0)]++;
  }
  std::vector<std::pair<int, long long>> ranked;
  for (const auto& [k, n] : votes) ranked.emplace_back(n, k);
  const size_t top = std::min<size_t>(8, ranked.size());
  std::partial_sort(ranked.begin(), ranked.begin() + long(top), ranked.end(), std::greater<>());
  double best = 0.0;
  int best_used = -1;
  for (size_t i = 0; i < top; ++i) {
    const double offset_s = double(ranked[i].second) / 1000.0;
    const int used = relations_error(relations, estimate, offset_s).used;
    if (used > best_used) {
      best_used = used;
      best = offset_s;
    }
  }
  return best;
}

RelationsError relations_error(const std::vector<Relation>& relations, const Trajectory& estimate, double offset_s,
                               double tolerance_s) {
  RelationsError out;
  out.total = int(relations.size());
  auto pose_at = [&](double t_s) -> std::optional<SE2> {
    const StampNs t = sec_to_ns(t_s - offset_s);
    auto it = std::lower_bound(estimate.begin(), estimate.end(), t,
                               [](const StampedPose& p, StampNs s) { return p.stamp_ns < s; });
    std::optional<SE2> best;
    double best_dt = tolerance_s;
    for (auto c : {it, it == estimate.begin() ? it : it - 1}) {
      if (c == estimate.end()) continue;
      const double dt = std::abs(ns_to_sec(c->stamp_ns - t));
      if (dt <= best_dt) {
        best_dt = dt;
        best = c->pose;
      }
    }
    return best;
  };
  std::vector<double> trans, rot;
  for (const Relation& r : relations) {
    const auto a = pose_at(r.t1_s), b = pose_at(r.t2_s);
    if (!a || !b) continue;
    const SE2 e = r.T_1_2.between(a->between(*b));
    trans.push_back(e.translation().norm());
    rot.push_back(std::abs(e.yaw()) * 180.0 / M_PI);
  }
  out.used = int(trans.size());
  out.trans_mean_m = mean_sd(trans, &out.trans_sd_m);
  out.rot_mean_deg = mean_sd(rot, &out.rot_sd_deg);
  return out;
}

}  // namespace cairn::slam
