#pragma once
#include <string>
#include <vector>

namespace arphys::config {

// A calibrated pinhole camera, read from an OpenCV calibration file
// (image_width, image_height, camera_matrix, distortion_coefficients; optional camera_id).
// Pixel convention: OpenCV's, the centre of the top-left pixel is (0, 0).
struct CameraConfig {
  std::string file;
  std::string camera_id;
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;
  std::vector<double> distortion;  // k1 k2 p1 p2 [k3 [k4 k5 k6 ...]]

  bool has_distortion() const;
};

// Throws ConfigError naming the file and key when the file is missing, unparsable, or
// holds a bad value (non-positive size or focal length, principal point outside the
// image, a distortion vector of a length OpenCV does not use).
CameraConfig load_camera(const std::string& path);

}  // namespace arphys::config
