#pragma once
#include <memory>
#include <string>
#include <vector>

#include "tracker/detection/apriltag_family_handle.hpp"
#include "tracker/detection/marker_detector.hpp"

struct apriltag_detector;

namespace arphys::tracking {

// libapriltag (3.3) behind the MarkerDetector interface.
//
// Parameters (set_param): decimate (quad_decimate, 1..8; default 2), sigma (quad_sigma,
// pixels; 0), refine_edges (1), sharpening (decode_sharpening; 0.25), threads (1),
// max_hamming (bits corrected, 0..2; 2).
//
// Predictive search (roi_tracking = 1, for video): every frame is searched at a coarse
// decimation (coarse_decimate, default 4: finds markers of >= ~60 px anywhere); markers
// of the previous frame the coarse pass missed are searched again in a window around
// their last corners; and one of scan_tiles tiles of the frame (default 64, in turn) is
// searched at full resolution, so a small marker that appears anywhere is found within
// scan_tiles frames. reset_prediction() forgets the previous frame (independent pictures).
// Corner accuracy comes from the pipeline's edge refinement, not the decimation.
//
// Corners come out in OpenCV's convention: libapriltag puts pixel centres at (0.5, 0.5)
// (apriltag issue #121), so 0.5 px is subtracted from each coordinate.
class AprilTagDetector final : public MarkerDetector {
 public:
  explicit AprilTagDetector(const std::vector<std::string>& families = {"tag36h11"});
  ~AprilTagDetector() override;

  std::vector<DetectedMarker> detect(const cv::Mat& gray) override;
  std::string implementation() const override { return "apriltag"; }
  std::string describe() const override;
  void set_param(const std::string& name, const std::string& value) override;
  std::vector<std::string> families() const override;
  void reset_prediction() override { previous_.clear(); }

 private:
  std::vector<DetectedMarker> detect_region(apriltag_detector* detector, const cv::Mat& gray, const cv::Rect& region);
  std::vector<DetectedMarker> detect_predictive(const cv::Mat& gray);

  std::vector<AprilTagFamilyHandle> families_;
  apriltag_detector* detector_ = nullptr;       // full frame at `decimate`, or coarse in ROI mode
  apriltag_detector* fine_detector_ = nullptr;  // full resolution, ROI mode only
  std::vector<AprilTagFamilyHandle> fine_families_;
  double decimate_ = 2.0;
  bool roi_tracking_ = false;
  double coarse_decimate_ = 4.0;
  int scan_tiles_ = 64;
  int next_tile_ = 0;
  std::vector<DetectedMarker> previous_;
};

}  // namespace arphys::tracking
