#include "robot_agent/core/navigation/goal_tracker.h"

#include <algorithm>
#include <cstdio>

namespace cairn::agent {

GoalTracker::GoalTracker(const GoalTrackerOptions& options) : options_(options) {}

void GoalTracker::change(NavState to, const std::string& reason) {
  last_ = NavTransition{state_, to, stamp_ns_, reason};
  state_ = to;
  ++transitions_;
}

void GoalTracker::start(const std::string& reason) {
  failures_ = 0;
  boxed_in_.clear();
  anchor_stamp_ns_.reset();
  recent_.clear();
  change(NavState::kDriving, reason);
}

void GoalTracker::cancel(const std::string& reason) { change(NavState::kIdle, reason); }

void GoalTracker::reached(StampNs stamp_ns, const std::string& reason) {
  stamp_ns_ = std::max(stamp_ns_, stamp_ns);
  if (state_ == NavState::kDriving) change(NavState::kReached, reason);
}

void GoalTracker::note_pose(StampNs stamp_ns, const Eigen::Vector2d& position_m) {
  if (stamp_ns < stamp_ns_) return;
  stamp_ns_ = stamp_ns;
  if (state_ != NavState::kDriving) return;
  recent_.emplace_back(stamp_ns, position_m);
  if (confined()) return;
  if (!anchor_stamp_ns_ || (position_m - anchor_m_).norm() >= options_.stuck_progress_m) {
    anchor_stamp_ns_ = stamp_ns;
    anchor_m_ = position_m;
    return;
  }
  const double idle_s = seconds_without_progress();
  if (idle_s < options_.stuck_after_s) return;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "no progress: moved %.2f m (< %.2f m) in %.1f s", (position_m - anchor_m_).norm(),
                options_.stuck_progress_m, idle_s);
  change(NavState::kStuck, boxed_in_.empty() ? std::string(buf) : std::string(buf) + "; " + boxed_in_);
}

bool GoalTracker::confined() {
  const StampNs window_start = stamp_ns_ - sec_to_ns(options_.confined_after_s);
  while (recent_.size() > 1 && recent_[1].first <= window_start) recent_.pop_front();
  if (recent_.front().first > window_start) return false;  // not watched that long yet
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& [stamp, p] : recent_) mean += p;
  mean /= double(recent_.size());
  double radius_m = 0;
  for (const auto& [stamp, p] : recent_) radius_m = std::max(radius_m, (p - mean).norm());
  if (radius_m >= options_.confined_radius_m) return false;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "no progress: stayed within %.2f m for %.1f s (back and forth)", radius_m,
                options_.confined_after_s);
  change(NavState::kStuck, boxed_in_.empty() ? std::string(buf) : std::string(buf) + "; " + boxed_in_);
  return true;
}

double GoalTracker::seconds_without_progress() const {
  return anchor_stamp_ns_ ? ns_to_sec(stamp_ns_ - *anchor_stamp_ns_) : 0.0;
}

void GoalTracker::plan_succeeded() {
  failures_ = 0;
  boxed_in_.clear();
}

void GoalTracker::plan_failed(bool first_plan, bool boxed_in, const std::string& why) {
  if (state_ != NavState::kDriving) return;
  if (boxed_in) {
    boxed_in_ = why;  // the stuck timer decides
    return;
  }
  boxed_in_.clear();
  ++failures_;
  if (first_plan) {
    change(NavState::kUnreachable, why);
  } else if (failures_ >= options_.max_plan_failures) {
    change(NavState::kUnreachable, "re-planning failed " + std::to_string(failures_) + " times in a row: " + why);
  }
}

}  // namespace cairn::agent
