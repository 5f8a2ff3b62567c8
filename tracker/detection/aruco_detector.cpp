#include "tracker/detection/aruco_detector.hpp"

#include <sstream>
#include <stdexcept>

#include "tracker/detection/marker_family.hpp"
#include "tracker/detection/param_parsing.hpp"

namespace arphys::tracking {

ArucoDetector::ArucoDetector(const std::vector<std::string>& families) : family_names_(families) {
  if (families.empty()) throw std::invalid_argument("ArucoDetector: no marker family given");
  for (const auto& family : families) {
    Dictionary d;
    d.apriltag_layout = is_apriltag_family(family) || family.rfind("DICT_APRILTAG_", 0) == 0;
    d.family = family.rfind("DICT_APRILTAG_", 0) == 0 ? "tag" + family.substr(14) : family;
    d.dictionary = cv::aruco::getPredefinedDictionary(aruco_dictionary_id(family));
    dictionaries_.push_back(d);
  }
  parameters_ = cv::aruco::DetectorParameters::create();
  parameters_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  parameters_->cornerRefinementWinSize = 2;
}

std::string ArucoDetector::describe() const {
  std::ostringstream out;
  out << "aruco families=";
  for (size_t i = 0; i < family_names_.size(); ++i) out << (i ? "," : "") << family_names_[i];
  out << " corner_refinement=" << refinement_;
  if (refinement_ == "subpix") out << " subpix_window=" << parameters_->cornerRefinementWinSize;
  if (parameters_->useAruco3Detection) out << " aruco3=1";
  return out.str();
}

void ArucoDetector::set_param(const std::string& name, const std::string& value) {
  if (name == "corner_refinement") {
    if (value == "none") {
      parameters_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_NONE;
    } else if (value == "subpix") {
      parameters_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
    } else if (value == "contour") {
      parameters_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_CONTOUR;
    } else if (value == "apriltag") {
      parameters_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_APRILTAG;
    } else {
      throw std::invalid_argument("parameter corner_refinement = '" + value +
                                  "': expected none, subpix, contour or apriltag");
    }
    refinement_ = value;
  } else if (name == "subpix_window") {
    parameters_->cornerRefinementWinSize = parse_param_int(name, value, 1, 20);
  } else if (name == "aruco3") {
    parameters_->useAruco3Detection = parse_param_bool(name, value);
  } else {
    throw std::invalid_argument("aruco has no parameter '" + name +
                                "' (expected corner_refinement, subpix_window, aruco3)");
  }
}

std::vector<DetectedMarker> ArucoDetector::detect(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("ArucoDetector::detect: expected a non-empty 8-bit single-channel image");
  }
  std::vector<DetectedMarker> markers;
  for (const auto& d : dictionaries_) {
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> ids;
    cv::aruco::detectMarkers(gray, d.dictionary, corners, ids, parameters_);
    for (size_t i = 0; i < ids.size(); ++i) {
      DetectedMarker m;
      m.family = d.family;
      m.id = ids[i];
      // OpenCV gives TL, TR, BR, BL of its own marker image. Its apriltag images are
      // libapriltag's rotated by 180 degrees, so its TL is the upright marker's BR.
      static constexpr int kClassic[4] = {3, 2, 1, 0};
      static constexpr int kAprilTag[4] = {1, 0, 3, 2};
      const int* order = d.apriltag_layout ? kAprilTag : kClassic;
      for (int k = 0; k < 4; ++k) {
        const cv::Point2f& p = corners[i][order[k]];
        m.corners_px[k] = Eigen::Vector2d(p.x, p.y);
      }
      markers.push_back(std::move(m));
    }
  }
  return markers;
}

}  // namespace arphys::tracking
