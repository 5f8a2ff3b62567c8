#pragma once
#include <chrono>

#include <opencv2/videoio.hpp>

#include "tracker/sources/frame_source.hpp"

namespace arphys::tracking {

// A V4L2 camera or a video file through OpenCV's VideoCapture.
// Capture time: for a camera, the driver's buffer timestamp (CAP_PROP_POS_MSEC, a
// monotonic clock) mapped to the wall clock, or the wall clock at grab when the driver
// gives none; for a file, the open time plus the frame's position in the stream, so a
// file plays with its own timing.
class VideoCaptureSource final : public FrameSource {
 public:
  // Device by index (V4L2).
  VideoCaptureSource(int device_index, int width, int height, double fps);
  // Video file.
  explicit VideoCaptureSource(const std::string& path);

  std::optional<Frame> next(int timeout_ms) override;
  bool finished() const override { return finished_; }
  std::string describe() const override { return description_; }
  int64_t skipped_frames() const override { return skipped_; }

 private:
  cv::VideoCapture capture_;
  bool is_file_ = false;
  bool finished_ = false;
  std::string description_;
  int64_t open_utime_ = 0;
  int64_t seq_ = 0;
  int64_t skipped_ = 0;
  int consecutive_failures_ = 0;
};

}  // namespace arphys::tracking
