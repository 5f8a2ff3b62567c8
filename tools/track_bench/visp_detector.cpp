#include "tools/track_bench/visp_detector.hpp"

#include <visp3/core/vpImage.h>
#include <visp3/detection/vpDetectorAprilTag.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace arphys::bench {
namespace {

class VispAprilTag : public tracking::MarkerDetector {
 public:
  explicit VispAprilTag(double quad_decimate) : decimate_(quad_decimate) {
    detector_.setAprilTagQuadDecimate(static_cast<float>(quad_decimate));
    detector_.setAprilTagNbThreads(1);
  }

  std::vector<tracking::DetectedMarker> detect(const cv::Mat& gray) override {
    if (gray.type() != CV_8UC1) throw std::invalid_argument("visp: expects an 8-bit single-channel image");
    image_.resize(static_cast<unsigned>(gray.rows), static_cast<unsigned>(gray.cols));
    for (int r = 0; r < gray.rows; ++r) std::memcpy(image_[r], gray.ptr(r), static_cast<std::size_t>(gray.cols));
    std::vector<tracking::DetectedMarker> found;
    if (!detector_.detect(image_)) return found;
    const std::vector<std::vector<vpImagePoint>> corners = detector_.getTagsCorners();
    const std::vector<int> ids = detector_.getTagsId();
    for (std::size_t k = 0; k < ids.size() && k < corners.size(); ++k) {
      tracking::DetectedMarker m;
      m.family = "tag36h11";
      m.id = ids[k];
      // ViSP passes apriltag's corners on (its order; u = j, v = i) in apriltag's pixel
      // convention, whose pixel centres sit at +0.5 of OpenCV's.
      for (int c = 0; c < 4; ++c) m.corners_px[c] = Eigen::Vector2d(corners[k][c].get_j() - 0.5, corners[k][c].get_i() - 0.5);
      found.push_back(m);
    }
    return found;
  }
  std::string implementation() const override { return "visp"; }
  std::string describe() const override { return "visp apriltag tag36h11 decimate=" + std::to_string(decimate_); }
  void set_param(const std::string& name, const std::string&) override {
    throw std::invalid_argument("visp: no parameter '" + name + "' in the benchmark's peer");
  }
  std::vector<std::string> families() const override { return {"tag36h11"}; }

 private:
  double decimate_;
  vpDetectorAprilTag detector_{vpDetectorAprilTag::TAG_36h11};
  vpImage<unsigned char> image_;
};

}  // namespace

std::unique_ptr<tracking::MarkerDetector> make_visp_apriltag(double quad_decimate) {
  return std::make_unique<VispAprilTag>(quad_decimate);
}

std::unique_ptr<tracking::MarkerDetector> make_bench_detector(const tracking::DetectorSpec& spec) {
  if (spec.implementation == "visp") return make_visp_apriltag(std::stod(spec.params.at(0).second));
  return tracking::make_detector(spec);
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(p * (values.size() - 1) + 0.5))];
}

}  // namespace arphys::bench
