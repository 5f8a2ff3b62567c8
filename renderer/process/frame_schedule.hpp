#pragma once
// The live renderer's frame policy without its transport: camera frames in, the frames due
// to be drawn out. Latency over completeness: only the newest frame waits; one it
// supersedes is dropped, except that a frame held for its own world state (wait_ms) is
// drawn rather than dropped when a newer one comes. A frame already handled (re-sent,
// replayed) or older than one is refused, so a video never goes back in time.
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lcmtypes/msg/frame_order.hpp"
#include "renderer/process/world_state_matcher.hpp"

namespace arphys::rendering {

struct ScheduleOptions {
  double wait_ms = 0;  // hold a frame up to this long for the world state computed from it
  MatchPolicy policy = MatchPolicy::kNearestEarlier;
};

// Frame: any type with camera_id, seq and utime (capture time, microseconds) members.
template <class Frame>
class FrameSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  // has_reached(capture_utime): the state computed from that frame, or from a later one, has
  // arrived (WorldStateMatcher::has_reached); then waiting longer gains nothing.
  FrameSchedule(ScheduleOptions options, std::function<bool(int64_t)> has_reached)
      : options_(options), has_reached_(std::move(has_reached)) {
    if (!(options_.wait_ms >= 0 && options_.wait_ms <= 1000)) {
      throw std::invalid_argument("wait_ms " + std::to_string(options_.wait_ms) + ": expected 0..1000");
    }
  }

  // A camera frame arrived at `now`. Returns kNew when it was kept.
  msg::FrameOrder::Verdict offer(Frame frame, Clock::time_point now) {
    const auto verdict = order_.check(frame.camera_id, frame.seq, frame.utime);
    if (verdict != msg::FrameOrder::Verdict::kNew) return verdict;
    if (pending_ && wait_left_ms(now) > 0 && !superseded_) {
      superseded_ = std::move(pending_);
    } else if (pending_) {
      ++dropped_;
    }
    pending_ = std::move(frame);
    pending_arrival_ = now;
    return verdict;
  }

  // How long the pending frame may still wait for its own world state (ms; 0: it is due).
  double wait_left_ms(Clock::time_point now) const {
    if (!pending_ || !waits() || has_reached_(pending_->utime)) return 0;
    return options_.wait_ms - std::chrono::duration<double, std::milli>(now - pending_arrival_).count();
  }

  // The frames to draw now, oldest first: a superseded frame at once, the pending one when
  // its wait is over.
  std::vector<Frame> take_due(Clock::time_point now) {
    std::vector<Frame> due;
    const bool hold = pending_ && wait_left_ms(now) > 0;
    if (superseded_) due.push_back(std::move(*superseded_));
    superseded_.reset();
    if (pending_ && !hold) {
      due.push_back(std::move(*pending_));
      pending_.reset();
    }
    for (const Frame& frame : due) {
      if (waits() && !has_reached_(frame.utime)) ++past_the_wait_;
    }
    return due;
  }

  // Frames dropped unseen because a newer one came first.
  int64_t dropped() const { return dropped_; }
  // Frames drawn without their own world state though they could have waited for it.
  int64_t past_the_wait() const { return past_the_wait_; }
  bool waits() const { return options_.wait_ms > 0 && options_.policy != MatchPolicy::kLatest; }

 private:
  ScheduleOptions options_;
  std::function<bool(int64_t)> has_reached_;
  msg::FrameOrder order_;
  std::optional<Frame> pending_, superseded_;
  Clock::time_point pending_arrival_;
  int64_t dropped_ = 0, past_the_wait_ = 0;
};

}  // namespace arphys::rendering
