#pragma once
#include <string>
#include <vector>

#include <opencv2/aruco.hpp>

#include "tracker/detection/marker_detector.hpp"
#include "tracker/detection/predictive_search.hpp"

namespace arphys::tracking {

// OpenCV 4.6's ArUco module behind the MarkerDetector interface.
//
// Families: ArUco dictionary names (DICT_4X4_50, ...) or apriltag family names that
// OpenCV knows (tag36h11 -> DICT_APRILTAG_36h11, reported as "tag36h11").
// Parameters (set_param): corner_refinement (none | subpix | contour | apriltag; default
// subpix), subpix_window (pixels, default 2: OpenCV's 5 flips half of the small markers),
// aruco3 (useAruco3Detection, default 0: in 4.6 it silently disables subpix refinement),
// min_marker_fraction and canonical_px (aruco3's minMarkerLengthRatioOriginalImg and
// minSideLengthCanonicalImg), threshold_step (adaptiveThreshWinSizeStep, default 10: 20
// thresholds the frame twice instead of three times), roi_tracking (default 0: 1 searches
// video frames through PredictiveSearch), coarse_decimate (its whole-frame pass, default
// 2) and scan_tiles (its scan, default 64).
//
// OpenCV's DICT_APRILTAG_* markers are libapriltag's images rotated by 180 degrees and
// its corners start at the image's top-left going clockwise; both are remapped to the
// common order (bottom-left, bottom-right, top-right, top-left of the upright marker).
class ArucoDetector final : public MarkerDetector {
 public:
  explicit ArucoDetector(const std::vector<std::string>& families = {"tag36h11"});

  std::vector<DetectedMarker> detect(const cv::Mat& gray) override;
  std::string implementation() const override { return "aruco"; }
  std::string describe() const override;
  void set_param(const std::string& name, const std::string& value) override;
  std::vector<std::string> families() const override { return family_names_; }
  void reset_prediction() override { search_.reset(); }

 private:
  std::vector<DetectedMarker> detect_region(const cv::Mat& gray, const cv::Rect& region, int decimation);

  struct Dictionary {
    std::string family;  // reported name
    bool apriltag_layout = false;
    cv::Ptr<cv::aruco::Dictionary> dictionary;
  };
  std::vector<std::string> family_names_;
  std::vector<Dictionary> dictionaries_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
  std::string refinement_ = "subpix";
  bool roi_tracking_ = false;
  int coarse_decimate_ = 2;
  PredictiveSearch search_;
};

}  // namespace arphys::tracking
