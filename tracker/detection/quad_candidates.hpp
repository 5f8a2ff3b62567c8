#pragma once
// Where in a still picture small markers may be: the quadrilaterals OpenCV's ArUco finds on
// the whole frame at full resolution (its adaptive thresholds and contours), the markers it
// decodes and the quads it rejects alike, each as a window for libapriltag to search at
// full resolution. libapriltag at decimation 2 loses markers under ~25 px (their black
// border is a pixel thick there) and at decimation 1 costs five times as much; its own
// segmentation over the whole frame is the cost, which the windows avoid.
#include <opencv2/aruco.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace arphys::tracking {

class QuadCandidates {
 public:
  // `families`: marker families OpenCV has as dictionaries (tag16h5, tag25h9, tag36h10,
  // tag36h11 or ArUco's own); throws std::invalid_argument naming one it lacks.
  explicit QuadCandidates(const std::vector<std::string>& families);
  // Windows around each quad (grown by a quarter of its size, at least 8 px, clipped to the
  // frame); a window at least half inside another is merged into it.
  std::vector<cv::Rect> windows(const cv::Mat& gray) const;

 private:
  std::vector<cv::Ptr<cv::aruco::Dictionary>> dictionaries_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
};

}  // namespace arphys::tracking
