#pragma once
#include <memory>
#include <string>
#include <vector>

#include "tracker/detection/apriltag_family_handle.hpp"
#include "tracker/detection/marker_detector.hpp"
#include "tracker/detection/predictive_search.hpp"
#include "tracker/detection/quad_candidates.hpp"

struct apriltag_detector;

namespace arphys::tracking {

// libapriltag (3.3) behind the MarkerDetector interface.
//
// Parameters (set_param): decimate (quad_decimate, 1..8; default 2), sigma (quad_sigma,
// pixels; 0), refine_edges (1), sharpening (decode_sharpening; 0.25), threads (1),
// max_hamming (bits corrected, 0..2; 2).
//
// Predictive search (roi_tracking = 1, for video; predictive_search.hpp): the coarse pass
// runs at coarse_decimate (default 4: finds markers of >= ~60 px anywhere), windows and
// scan tiles (scan_tiles, default 64) at full or half resolution. reset_prediction()
// forgets the previous frame (independent pictures).
//
// Candidate search (candidate_search = 1, for stills; quad_candidates.hpp): the quads
// OpenCV's ArUco finds on the whole frame, each searched by libapriltag at full resolution
// (decimation 2 for windows over 120 px); for families OpenCV has (tag16h5, tag25h9,
// tag36h10, tag36h11).
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
  void reset_prediction() override { search_.reset(); }

 private:
  std::vector<DetectedMarker> detect_region(apriltag_detector* detector, const cv::Mat& gray, const cv::Rect& region);
  std::vector<DetectedMarker> detect_predictive(const cv::Mat& gray);
  std::vector<DetectedMarker> detect_candidates(const cv::Mat& gray);
  apriltag_detector* fine_detector();

  std::vector<AprilTagFamilyHandle> families_;
  apriltag_detector* detector_ = nullptr;       // full frame at `decimate`, or coarse in ROI mode
  apriltag_detector* fine_detector_ = nullptr;  // full resolution, ROI mode only
  std::vector<AprilTagFamilyHandle> fine_families_;
  double decimate_ = 2.0;
  bool roi_tracking_ = false;
  double coarse_decimate_ = 4.0;
  PredictiveSearch search_;
  std::unique_ptr<QuadCandidates> candidates_;  // candidate search, when on
};

}  // namespace arphys::tracking
