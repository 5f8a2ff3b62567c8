#include <stdexcept>

#include "tracker/detection/apriltag_detector.hpp"
#include "tracker/detection/aruco_detector.hpp"
#include "tracker/detection/marker_detector.hpp"

namespace arphys::tracking {

std::vector<std::string> detector_implementations() { return {"apriltag", "aruco"}; }

std::unique_ptr<MarkerDetector> make_detector(const DetectorSpec& spec) {
  const std::vector<std::string> families = spec.families.empty() ? std::vector<std::string>{"tag36h11"} : spec.families;
  std::unique_ptr<MarkerDetector> detector;
  if (spec.implementation == "apriltag") {
    detector = std::make_unique<AprilTagDetector>(families);
  } else if (spec.implementation == "aruco") {
    detector = std::make_unique<ArucoDetector>(families);
  } else {
    throw std::invalid_argument("unknown detector implementation '" + spec.implementation +
                                "' (expected apriltag or aruco)");
  }
  for (const auto& [name, value] : spec.params) detector->set_param(name, value);
  return detector;
}

}  // namespace arphys::tracking
