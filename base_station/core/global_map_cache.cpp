#include "base_station/core/global_map_cache.h"

namespace cairn::base {

void GlobalMapCache::poses_changed() {
  if (tracked_version_ == poses_version_) ++tracked_version_;  // still in step: the list accounts for it
  ++poses_version_;
}

void GlobalMapCache::bound(size_t keyframes) {
  if (moved_.size() > keyframes) all_moved_ = true;
  if (all_moved_) moved_.clear();
}

const OccupancyGrid& GlobalMapCache::render(const MapperData& data) {
  if (rendered_version_ == poses_version_) return renderer_.render();
  std::map<RobotId, SE2> corrections;
  for (const auto& [id, start] : data.starts) corrections[id] = data.correction(id);
  auto place = [&](const Keyframe& kf, const SE2* optimised) {
    auto c = corrections.find(kf.id.robot);
    if (c == corrections.end()) {  // not linked: not placed
      renderer_.remove(kf.id);
    } else {
      renderer_.set_pose(kf, optimised ? *optimised : c->second * kf.T_local_base);
    }
  };
  if (all_moved_ || tracked_version_ != poses_version_) {
    auto opt = data.optimized.begin();  // one merge pass: both maps are in id order
    for (const auto& [id, kf] : data.keyframes) {
      while (opt != data.optimized.end() && opt->first < id) ++opt;
      place(kf, opt != data.optimized.end() && opt->first == id ? &opt->second : nullptr);
    }
  } else {
    for (KeyframeId id : moved_) {
      auto kf = data.keyframes.find(id);
      auto opt = data.optimized.find(id);
      if (kf != data.keyframes.end()) place(kf->second, opt != data.optimized.end() ? &opt->second : nullptr);
    }
  }
  moved_.clear();
  all_moved_ = false;
  tracked_version_ = poses_version_;
  rendered_version_ = poses_version_;
  return renderer_.render();
}

}  // namespace cairn::base
