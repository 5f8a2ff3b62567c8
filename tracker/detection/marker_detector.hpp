#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace arphys::tracking {

// One marker found in an image, before any pose is computed.
struct DetectedMarker {
  std::string family;  // "tag36h11", "DICT_4X4_50", ... (ArUco's AprilTag dictionary reports "tag36h11")
  int id = 0;
  // Corners in OpenCV's pixel convention (the centre of the top-left pixel is (0, 0)),
  // in apriltag's order as seen from the marker's front: bottom-left, bottom-right,
  // top-right, top-left. Every detector reports this order and convention, so the
  // implementations are interchangeable downstream.
  std::array<Eigen::Vector2d, 4> corners_px;
  double decision_margin = 0;  // apriltag's decision margin; 0 where the detector gives none
  int hamming = -1;            // corrected bits; -1 where unknown
};

// A fiducial detector: one implementation per library (apriltag's small flat C API is
// the model: create, set parameters, detect). Not thread-safe; one per thread.
class MarkerDetector {
 public:
  virtual ~MarkerDetector() = default;
  // Detects markers in an 8-bit single-channel image.
  virtual std::vector<DetectedMarker> detect(const cv::Mat& gray) = 0;
  // "apriltag" or "aruco".
  virtual std::string implementation() const = 0;
  // The implementation and its parameters in short, for messages and logs.
  virtual std::string describe() const = 0;
  // Sets a parameter by name from its text value. Throws std::invalid_argument naming
  // the parameter, the value and what is expected when either is bad.
  virtual void set_param(const std::string& name, const std::string& value) = 0;
  // The marker families this detector looks for.
  virtual std::vector<std::string> families() const = 0;
  // Detectors that search near last frame's markers forget them (the next image is
  // unrelated: a folder of photos, a seek, a camera switch). Default: nothing kept.
  virtual void reset_prediction() {}
};

// Parameters that make a detector, from `--impl` and name=value overrides.
struct DetectorSpec {
  std::string implementation = "apriltag";  // "apriltag" | "aruco"
  std::vector<std::string> families;         // empty: tag36h11
  std::vector<std::pair<std::string, std::string>> params;
};

// Throws std::invalid_argument for an unknown implementation, family or parameter.
std::unique_ptr<MarkerDetector> make_detector(const DetectorSpec& spec);

// The implementations make_detector knows.
std::vector<std::string> detector_implementations();

}  // namespace arphys::tracking
