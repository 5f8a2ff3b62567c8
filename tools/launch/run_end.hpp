#pragma once
// When a launched run is over. With the synthetic camera the run is its script: it ends
// once the camera has published its last frame and the pipeline has carried that frame
// through (no frame message for kSettledS), at most kDrainS after the camera; a camera
// drawing slower than its frame rate (a loaded machine) is waited for, up to
// kCameraLateLimitS past the duration. Any other source: the given duration, then kDrainS.
#include <algorithm>
#include <cstdint>
#include <string>

namespace arphys::launch {

class RunEnd {
 public:
  static constexpr double kDrainS = 2.5, kSettledS = 0.5, kCameraLateLimitS = 20.0;

  RunEnd(double duration_s, bool camera_script) : duration_s_(duration_s), camera_script_(camera_script) {}

  // At elapsed_s into the run: whether the camera has exited and how many frame messages
  // have been seen so far. True when the run is over; why() then says why.
  bool over(double elapsed_s, bool camera_exited, int64_t frame_messages) {
    if (!camera_script_) {
      if (elapsed_s > duration_s_ + kDrainS) why_ = "duration";
      return !why_.empty();
    }
    if (camera_exited && camera_done_s_ < 0) camera_done_s_ = elapsed_s;
    if (frame_messages != frame_messages_) {
      frame_messages_ = frame_messages;
      last_frame_message_s_ = elapsed_s;
    }
    if (camera_done_s_ >= 0) {
      drain_s_ = elapsed_s - camera_done_s_;
      const double quiet_s = elapsed_s - std::max(last_frame_message_s_, camera_done_s_);
      if (quiet_s > kSettledS) why_ = "settled";
      else if (drain_s_ > kDrainS) why_ = "drain_limit";
    } else if (elapsed_s > duration_s_ + kCameraLateLimitS) {
      why_ = "camera_late";
    }
    return !why_.empty();
  }

  // "settled", "drain_limit", "camera_late", "duration" (empty: not over).
  const std::string& why() const { return why_; }
  // Seconds from the camera's end to the run's end.
  double drain_s() const { return drain_s_; }

 private:
  double duration_s_;
  bool camera_script_;
  double camera_done_s_ = -1, last_frame_message_s_ = 0, drain_s_ = 0;
  int64_t frame_messages_ = -1;
  std::string why_;
};

}  // namespace arphys::launch
