#include "tracker/detection/aruco_detector.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "tracker/detection/marker_family.hpp"
#include "tracker/detection/param_parsing.hpp"

namespace arphys::tracking {

namespace {
// Markers smaller than this (pixels) found by the coarse pass are found again at full
// resolution: at half resolution a 40 px marker's corners are a pixel off.
constexpr int kRefineBelowPx = 60;
}  // namespace

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
  search_.set_refine_coarse_below_px(kRefineBelowPx);
}

std::string ArucoDetector::describe() const {
  std::ostringstream out;
  out << "aruco families=";
  for (size_t i = 0; i < family_names_.size(); ++i) out << (i ? "," : "") << family_names_[i];
  out << " corner_refinement=" << refinement_;
  if (refinement_ == "subpix") out << " subpix_window=" << parameters_->cornerRefinementWinSize;
  if (parameters_->useAruco3Detection) out << " aruco3=1";
  if (roi_tracking_)
    out << " roi_tracking=1 coarse_decimate=" << coarse_decimate_ << " scan_tiles=" << search_.scan_tiles()
        << " coarse_every=" << search_.coarse_every();
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
  } else if (name == "min_marker_fraction") {
    parameters_->minMarkerLengthRatioOriginalImg = static_cast<float>(parse_param_double(name, value, 0.0, 1.0));
  } else if (name == "canonical_px") {
    parameters_->minSideLengthCanonicalImg = parse_param_int(name, value, 8, 128);
  } else if (name == "threshold_step") {
    parameters_->adaptiveThreshWinSizeStep = parse_param_int(name, value, 1, 100);
  } else if (name == "roi_tracking") {
    roi_tracking_ = parse_param_bool(name, value);
    search_.reset();
  } else if (name == "coarse_decimate") {
    coarse_decimate_ = parse_param_int(name, value, 1, 8);
    search_.set_refine_coarse_below_px(coarse_decimate_ > 1 ? kRefineBelowPx : 0);  // full resolution needs none
  } else if (name == "scan_tiles") {
    search_.set_scan_tiles(parse_param_int(name, value, 0, 256));
  } else if (name == "coarse_every") {
    search_.set_coarse_every(parse_param_int(name, value, 1, 30));
  } else {
    throw std::invalid_argument(
        "aruco has no parameter '" + name +
        "' (expected corner_refinement, subpix_window, aruco3, min_marker_fraction, "
        "canonical_px, threshold_step, roi_tracking, coarse_decimate, scan_tiles, coarse_every)");
  }
}

std::vector<DetectedMarker> ArucoDetector::detect(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("ArucoDetector::detect: expected a non-empty 8-bit single-channel image");
  }
  if (!roi_tracking_) return detect_region(gray, cv::Rect(0, 0, gray.cols, gray.rows), 1);
  return search_.detect(
      gray, [this](const cv::Mat& g) { return detect_region(g, cv::Rect(0, 0, g.cols, g.rows), coarse_decimate_); },
      [this](const cv::Mat& g, const cv::Rect& region, int decimation) { return detect_region(g, region, decimation); });
}

std::vector<DetectedMarker> ArucoDetector::detect_region(const cv::Mat& gray, const cv::Rect& region, int decimation) {
  cv::Mat image = gray(region);
  if (decimation > 1) {
    cv::Mat small;
    cv::resize(image, small, cv::Size(), 1.0 / decimation, 1.0 / decimation, cv::INTER_AREA);
    image = small;
  }
  const double fx = static_cast<double>(region.width) / image.cols, fy = static_cast<double>(region.height) / image.rows;
  // ArUco's smallest marker is a fraction of the picture's larger side: in a window that is
  // a fraction of the frame's, so in a 150 px window a 5 px contour became a candidate and
  // a window cost as much as the whole frame at half resolution. The smallest marker stays
  // the whole frame's, in frame pixels.
  cv::Ptr<cv::aruco::DetectorParameters> parameters = parameters_;
  const double frame_side_px = std::max(gray.cols, gray.rows), searched_side_px = std::max(region.width, region.height);
  if (searched_side_px < frame_side_px) {
    parameters = cv::makePtr<cv::aruco::DetectorParameters>(*parameters_);
    parameters->minMarkerPerimeterRate = std::min(
        parameters_->maxMarkerPerimeterRate, parameters_->minMarkerPerimeterRate * frame_side_px / searched_side_px);
  }
  std::vector<DetectedMarker> markers;
  for (const auto& d : dictionaries_) {
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> ids;
    cv::aruco::detectMarkers(image, d.dictionary, corners, ids, parameters);
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
        // Pixel centres at integers on both grids: x_full + 0.5 = (x_small + 0.5) * f.
        m.corners_px[k] = Eigen::Vector2d((p.x + 0.5) * fx - 0.5 + region.x, (p.y + 0.5) * fy - 0.5 + region.y);
      }
      markers.push_back(std::move(m));
    }
  }
  return markers;
}

}  // namespace arphys::tracking
