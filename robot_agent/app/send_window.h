#pragma once
// Keyframes in flight on a slow radio: what the agent has made waits here, oldest first, and is
// handed to DDS only while fewer than `limit` keyframes are written but not acknowledged by the
// base. A reliable reader delivers in order, and a lost sample's repair queues behind everything
// its writer has queued; with the whole backlog handed to DDS at once, four robots on 100 kbit/s
// saw repairs wait minutes while the base stayed stuck at one robot's 28th keyframe. Kept in the
// agent instead, the backlog costs nothing on the radio and the queue in DDS stays a few seconds
// long. (TCP's window, without its congestion control: the flow controller sets the rate.)
#include <algorithm>
#include <cstdint>
#include <deque>
#include <utility>

namespace cairn::agent {

/// T has `int32_t seq() const` (consecutive from 0 within a session).
template <typename T>
class SendWindow {
 public:
  /// limit <= 0: no limit (everything is released at once).
  explicit SendWindow(int limit = 0) : limit_(limit) {}

  void push(T sample) { waiting_.push_back(std::move(sample)); }
  /// The base has everything up to and including `seq`.
  void acknowledged(int32_t seq) { acked_seq_ = std::max(acked_seq_, seq); }
  /// Hands every sample that fits in the window to `write`, oldest first; returns how many.
  template <typename Write>
  int release(Write&& write) {
    int n = 0;
    while (!waiting_.empty() && (limit_ <= 0 || waiting_.front().seq() - acked_seq_ <= limit_)) {
      write(waiting_.front());
      waiting_.pop_front();
      ++n;
    }
    return n;
  }
  bool empty() const { return waiting_.empty(); }
  size_t waiting() const { return waiting_.size(); }

 private:
  int limit_;
  int32_t acked_seq_ = -1;
  std::deque<T> waiting_;
};

}  // namespace cairn::agent
