#pragma once
// Shared fixtures of the tracker tests: a 640x480 pinhole camera and markers rendered
// at known poses (tracker/synthetic), so every figure is checked against exact truth.
#include <cmath>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "tracker/detection/edge_refinement.hpp"
#include "tracker/detection/marker_detector.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace arphys::tracking::testing {

inline CameraModel test_camera() {
  CameraModel camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.K = cv::Matx33d(600, 0, 319.5, 0, 600, 239.5, 0, 0, 1);
  return camera;
}

inline double degrees(double rad) { return rad * 180.0 / M_PI; }

// Largest corner distance between a detection and the truth, pixels.
inline double max_corner_error_px(const DetectedMarker& d, const std::array<Eigen::Vector2d, 4>& truth) {
  double worst = 0;
  for (int k = 0; k < 4; ++k) worst = std::max(worst, (d.corners_px[k] - truth[k]).norm());
  return worst;
}

inline const DetectedMarker* find_marker(const std::vector<DetectedMarker>& markers, int id) {
  for (const auto& m : markers) {
    if (m.id == id) return &m;
  }
  return nullptr;
}

// The apriltag repository's reference detections of one photo (`<name>.txt`): per line
// the id and four corners, converted to OpenCV's pixel convention (-0.5 px).
struct ReferenceDetection {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners_px;
};
inline std::vector<ReferenceDetection> read_reference_detections(const std::string& path) {
  std::vector<ReferenceDetection> refs;
  std::ifstream in(path);
  std::string line;
  const std::regex number(R"([-0-9.]+)");
  while (std::getline(in, line)) {
    std::vector<double> v;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), number); it != std::sregex_iterator(); ++it) {
      v.push_back(std::stod(it->str()));
    }
    if (v.size() != 9) continue;
    ReferenceDetection r;
    r.id = static_cast<int>(v[0]);
    for (int k = 0; k < 4; ++k) r.corners_px[k] = Eigen::Vector2d(v[1 + 2 * k] - 0.5, v[2 + 2 * k] - 0.5);
    refs.push_back(r);
  }
  return refs;
}

// Detection followed by the pipeline's edge refinement, as the tracker runs it.
inline std::vector<DetectedMarker> detect_refined(MarkerDetector& detector, const cv::Mat& image) {
  std::vector<DetectedMarker> found = detector.detect(image);
  for (auto& m : found) refine_corners_on_edges(image, m);
  return found;
}

}  // namespace arphys::tracking::testing
