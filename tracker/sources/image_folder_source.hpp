#pragma once
#include <vector>

#include "tracker/sources/frame_source.hpp"

namespace arphys::tracking {

// The images of a folder (png, jpg, jpeg, bmp, pgm, ppm, tif, tiff) in name order, as
// independent pictures at a nominal frame rate: frame i is stamped open time + i / fps.
// An image that does not decode is skipped and counted.
class ImageFolderSource final : public FrameSource {
 public:
  ImageFolderSource(const std::string& folder, double fps);

  std::optional<Frame> next(int timeout_ms) override;
  bool finished() const override { return index_ >= files_.size(); }
  bool frames_independent() const override { return true; }
  std::string describe() const override { return folder_ + " (" + std::to_string(files_.size()) + " images)"; }
  int64_t skipped_frames() const override { return skipped_; }

 private:
  std::string folder_;
  std::vector<std::string> files_;
  size_t index_ = 0;
  double fps_;
  int64_t open_utime_ = 0;
  int64_t skipped_ = 0;
};

}  // namespace arphys::tracking
