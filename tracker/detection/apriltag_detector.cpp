#include "tracker/detection/apriltag_detector.hpp"

#include <apriltag/apriltag.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tracker/detection/param_parsing.hpp"
#include "tracker/detection/predictive_search.hpp"

namespace arphys::tracking {

namespace {

// Candidate windows wider than this are searched at half resolution (candidate_search).
constexpr int kHalfResolutionWindowPx = 120;

apriltag_detector_t* create_detector(std::vector<AprilTagFamilyHandle>& families, const std::vector<std::string>& names) {
  apriltag_detector_t* detector = apriltag_detector_create();
  for (const auto& name : names) {
    families.emplace_back(name);
    apriltag_detector_add_family_bits(detector, families.back().get(), 2);
  }
  detector->nthreads = 1;
  detector->quad_decimate = 2.0f;
  detector->quad_sigma = 0.0f;
  detector->refine_edges = true;
  detector->decode_sharpening = 0.25;
  return detector;
}

}  // namespace

AprilTagDetector::AprilTagDetector(const std::vector<std::string>& families) {
  if (families.empty()) throw std::invalid_argument("AprilTagDetector: no marker family given");
  detector_ = create_detector(families_, families);
}

AprilTagDetector::~AprilTagDetector() {
  if (detector_) apriltag_detector_destroy(detector_);
  if (fine_detector_) apriltag_detector_destroy(fine_detector_);
}

std::vector<std::string> AprilTagDetector::families() const {
  std::vector<std::string> names;
  for (const auto& f : families_) names.push_back(f.name());
  return names;
}

std::string AprilTagDetector::describe() const {
  std::ostringstream out;
  out << "apriltag families=";
  for (size_t i = 0; i < families_.size(); ++i) out << (i ? "," : "") << families_[i].name();
  out << " decimate=" << decimate_ << " sigma=" << detector_->quad_sigma << " refine_edges=" << detector_->refine_edges
      << " threads=" << detector_->nthreads;
  if (candidates_) out << " candidate_search=1";
  if (roi_tracking_)
    out << " roi_tracking=1 coarse_decimate=" << coarse_decimate_ << " scan_tiles=" << search_.scan_tiles()
        << " coarse_every=" << search_.coarse_every();
  return out.str();
}

void AprilTagDetector::set_param(const std::string& name, const std::string& value) {
  if (name == "decimate") {
    decimate_ = parse_param_double(name, value, 1.0, 8.0);
    if (!roi_tracking_) detector_->quad_decimate = static_cast<float>(decimate_);
  } else if (name == "sigma") {
    detector_->quad_sigma = static_cast<float>(parse_param_double(name, value, 0.0, 10.0));
  } else if (name == "refine_edges") {
    detector_->refine_edges = parse_param_bool(name, value);
  } else if (name == "sharpening") {
    detector_->decode_sharpening = parse_param_double(name, value, 0.0, 10.0);
  } else if (name == "threads") {
    detector_->nthreads = parse_param_int(name, value, 1, 64);
  } else if (name == "max_hamming") {
    const int bits = parse_param_int(name, value, 0, 2);
    apriltag_detector_clear_families(detector_);
    for (auto& f : families_) apriltag_detector_add_family_bits(detector_, f.get(), bits);
  } else if (name == "roi_tracking") {
    roi_tracking_ = parse_param_bool(name, value);
    detector_->quad_decimate = static_cast<float>(roi_tracking_ ? coarse_decimate_ : decimate_);
    search_.reset();
  } else if (name == "coarse_decimate") {
    coarse_decimate_ = parse_param_double(name, value, 1.0, 8.0);
    if (roi_tracking_) detector_->quad_decimate = static_cast<float>(coarse_decimate_);
  } else if (name == "scan_tiles") {
    search_.set_scan_tiles(parse_param_int(name, value, 0, 256));
  } else if (name == "coarse_every") {
    search_.set_coarse_every(parse_param_int(name, value, 1, 30));
  } else if (name == "candidate_search") {
    candidates_ = parse_param_bool(name, value) ? std::make_unique<QuadCandidates>(families()) : nullptr;
  } else {
    throw std::invalid_argument("apriltag has no parameter '" + name +
                                "' (expected decimate, sigma, refine_edges, sharpening, threads, max_hamming, "
                                "roi_tracking, coarse_decimate, scan_tiles, coarse_every, candidate_search)");
  }
}

std::vector<DetectedMarker> AprilTagDetector::detect_region(apriltag_detector* detector, const cv::Mat& gray,
                                                            const cv::Rect& region) {
  // A view into the caller's pixels: no copy, apriltag only reads them.
  image_u8_t image{region.width, region.height, static_cast<int32_t>(gray.step[0]),
                   const_cast<uint8_t*>(gray.ptr<uint8_t>(region.y) + region.x)};
  zarray_t* detections = apriltag_detector_detect(detector, &image);
  std::vector<DetectedMarker> markers;
  markers.reserve(zarray_size(detections));
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(detections, i, &d);
    DetectedMarker m;
    m.family = d->family->name;
    m.id = d->id;
    for (int k = 0; k < 4; ++k) {
      m.corners_px[k] = Eigen::Vector2d(d->p[k][0] - 0.5 + region.x, d->p[k][1] - 0.5 + region.y);
    }
    m.decision_margin = d->decision_margin;
    m.hamming = d->hamming;
    markers.push_back(std::move(m));
  }
  apriltag_detections_destroy(detections);
  return markers;
}

std::vector<DetectedMarker> AprilTagDetector::detect(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1) {
    throw std::invalid_argument("AprilTagDetector::detect: expected a non-empty 8-bit single-channel image");
  }
  if (roi_tracking_) return detect_predictive(gray);
  if (candidates_) return detect_candidates(gray);
  return detect_region(detector_, gray, cv::Rect(0, 0, gray.cols, gray.rows));
}

apriltag_detector* AprilTagDetector::fine_detector() {
  if (!fine_detector_) {
    fine_detector_ = create_detector(fine_families_, families());
    fine_detector_->quad_decimate = 1.0f;
  }
  fine_detector_->quad_sigma = detector_->quad_sigma;
  fine_detector_->decode_sharpening = detector_->decode_sharpening;
  fine_detector_->refine_edges = detector_->refine_edges;
  return fine_detector_;
}

std::vector<DetectedMarker> AprilTagDetector::detect_candidates(const cv::Mat& gray) {
  apriltag_detector* fine = fine_detector();
  std::vector<DetectedMarker> found;
  for (const cv::Rect& window : candidates_->windows(gray)) {
    // A large window holds a large marker: half resolution finds it.
    fine->quad_decimate = std::max(window.width, window.height) > kHalfResolutionWindowPx ? 2.0f : 1.0f;
    for (DetectedMarker& m : detect_region(fine, gray, window)) {
      // Windows overlap: a marker found twice is kept once.
      const auto same = [&](const DetectedMarker& f) {
        return f.id == m.id && f.family == m.family && (f.corners_px[0] - m.corners_px[0]).norm() < 2.0;
      };
      if (std::none_of(found.begin(), found.end(), same)) found.push_back(std::move(m));
    }
  }
  return found;
}

std::vector<DetectedMarker> AprilTagDetector::detect_predictive(const cv::Mat& gray) {
  fine_detector();
  return search_.detect(
      gray, [this](const cv::Mat& g) { return detect_region(detector_, g, cv::Rect(0, 0, g.cols, g.rows)); },
      [this](const cv::Mat& g, const cv::Rect& region, int decimation) {
        fine_detector_->quad_decimate = static_cast<float>(decimation);
        return detect_region(fine_detector_, g, region);
      });
}

}  // namespace arphys::tracking
