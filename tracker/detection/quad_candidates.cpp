#include "tracker/detection/quad_candidates.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "tracker/detection/marker_family.hpp"

namespace arphys::tracking {

QuadCandidates::QuadCandidates(const std::vector<std::string>& families) {
  for (const auto& family : families)
    dictionaries_.push_back(cv::aruco::getPredefinedDictionary(aruco_dictionary_id(family)));
  parameters_ = cv::aruco::DetectorParameters::create();
  // Two adaptive thresholds (3 and 23 px windows), corners unrefined: libapriltag fits them.
  parameters_->adaptiveThreshWinSizeStep = 20;
  parameters_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_NONE;
}

std::vector<cv::Rect> QuadCandidates::windows(const cv::Mat& gray) const {
  const cv::Rect frame(0, 0, gray.cols, gray.rows);
  std::vector<cv::Rect> out;
  const auto add = [&](const std::vector<cv::Point2f>& quad) {
    const cv::Rect b = cv::boundingRect(quad);
    const int grow = std::max(8, std::max(b.width, b.height) / 4);
    const cv::Rect w = cv::Rect(b.x - grow, b.y - grow, b.width + 2 * grow, b.height + 2 * grow) & frame;
    if (w.area() > 0) out.push_back(w);
  };
  for (const auto& dictionary : dictionaries_) {
    std::vector<std::vector<cv::Point2f>> corners, rejected;
    std::vector<int> ids;
    cv::aruco::detectMarkers(gray, dictionary, corners, ids, parameters_, rejected);
    for (const auto& q : corners) add(q);
    for (const auto& q : rejected) add(q);
  }
  // A window mostly inside another (a marker's inner quads, its quad at both thresholds) is
  // merged into it. Windows that merely touch stay apart: chained, a cluttered picture's
  // windows grew into one large region searched at full resolution.
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < out.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < out.size() && !merged; ++j)
        if (2 * (out[i] & out[j]).area() >= std::min(out[i].area(), out[j].area())) {
          out[i] |= out[j];
          out.erase(out.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
  }
  return out;
}

}  // namespace arphys::tracking
