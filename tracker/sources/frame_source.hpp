#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>

namespace arphys::tracking {

// One camera frame as it leaves its source.
struct Frame {
  cv::Mat image;              // 8-bit grey or BGR
  int64_t capture_utime = 0;  // capture time, microseconds since the Unix epoch
  int64_t seq = 0;            // source sequence number, one per captured frame
  std::string name;           // file name for folder sources, empty otherwise
};

// Thrown when a source cannot be opened or read; the message names the source.
class SourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where frames come from: a V4L2 camera, a video file, a folder of images, or an LCM
// image channel (the last lives with the tracker executable, which owns the LCM bus).
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // The next frame, waiting up to timeout_ms for a live source. nullopt: no frame yet
  // (live) or none left (see finished()).
  virtual std::optional<Frame> next(int timeout_ms) = 0;
  // True when a finite source (file, folder) has delivered its last frame.
  virtual bool finished() const = 0;
  // Frames are unrelated pictures (a folder of photos): no prediction across them.
  virtual bool frames_independent() const { return false; }
  virtual std::string describe() const = 0;
  // Frames that could not be read or decoded and were skipped.
  virtual int64_t skipped_frames() const { return 0; }
};

// Opens a source from its command-line spelling: "/dev/videoN" or "cam:N" (V4L2),
// a directory (images in name order, fps_hint frames per second for their capture
// times), or a video file. lcm: sources are opened by the executable. Throws
// SourceError for a missing path, an empty folder or a device or file OpenCV cannot open.
// width/height/fps request a mode from a camera (0 keeps the driver's).
std::unique_ptr<FrameSource> open_frame_source(const std::string& spec, double fps_hint = 30.0, int width = 0,
                                               int height = 0, double camera_fps = 0);

}  // namespace arphys::tracking
