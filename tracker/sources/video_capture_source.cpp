#include "tracker/sources/video_capture_source.hpp"

#include <time.h>

#include <cmath>

#include "tracker/sources/wall_clock.hpp"

namespace arphys::tracking {

namespace {

int64_t monotonic_utime() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
}

}  // namespace

VideoCaptureSource::VideoCaptureSource(int device_index, int width, int height, double fps) {
  description_ = "/dev/video" + std::to_string(device_index);
  if (!capture_.open(device_index, cv::CAP_V4L2)) {
    throw SourceError("cannot open camera " + description_ +
                      " (no such device, or it is busy; list devices with `v4l2-ctl --list-devices`)");
  }
  if (width > 0) capture_.set(cv::CAP_PROP_FRAME_WIDTH, width);
  if (height > 0) capture_.set(cv::CAP_PROP_FRAME_HEIGHT, height);
  if (fps > 0) capture_.set(cv::CAP_PROP_FPS, fps);
  open_utime_ = wall_clock_utime();
}

VideoCaptureSource::VideoCaptureSource(const std::string& path) : is_file_(true) {
  description_ = path;
  if (!capture_.open(path)) throw SourceError("cannot open video file " + path + " (missing, or not a video OpenCV can decode)");
  open_utime_ = wall_clock_utime();
}

std::optional<Frame> VideoCaptureSource::next(int /*timeout_ms*/) {
  if (finished_) return std::nullopt;
  Frame frame;
  if (!capture_.read(frame.image) || frame.image.empty()) {
    // A file ends; a camera that keeps failing has gone away.
    if (is_file_ || ++consecutive_failures_ > 30) finished_ = true;
    if (!is_file_) ++skipped_;
    return std::nullopt;
  }
  consecutive_failures_ = 0;
  const double position_ms = capture_.get(cv::CAP_PROP_POS_MSEC);
  if (is_file_) {
    frame.capture_utime = open_utime_ + static_cast<int64_t>(std::llround(position_ms * 1000.0));
  } else if (position_ms > 0) {
    // V4L2 buffer timestamps are CLOCK_MONOTONIC: shift them onto the wall clock.
    const int64_t age_us = monotonic_utime() - static_cast<int64_t>(std::llround(position_ms * 1000.0));
    frame.capture_utime = (age_us >= 0 && age_us < 1000000) ? wall_clock_utime() - age_us : wall_clock_utime();
  } else {
    frame.capture_utime = wall_clock_utime();
  }
  frame.seq = seq_++;
  return frame;
}

}  // namespace arphys::tracking
