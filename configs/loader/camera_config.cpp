#include "configs/loader/camera_config.hpp"

#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <sstream>

#include "configs/loader/config_error.hpp"

namespace arphys::config {

Eigen::Matrix3d CameraConfig::intrinsic_matrix() const {
  Eigen::Matrix3d K;
  K << fx_px, 0, cx_px, 0, fy_px, cy_px, 0, 0, 1;
  return K;
}

bool CameraConfig::has_distortion() const {
  for (double d : distortion)
    if (d != 0.0) return true;
  return false;
}

namespace {

template <class T>
std::string str(const T& value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace

CameraConfig load_camera(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw ConfigError(path, 0, "", "camera file does not exist (expected an OpenCV calibration YAML file)");
  }
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ)) {
      throw ConfigError(path, 0, "", "cannot be opened as an OpenCV calibration file");
    }
  } catch (const cv::Exception& e) {
    throw ConfigError(path, 0, "", std::string("not a valid OpenCV YAML file: ") + e.err);
  }
  CameraConfig cam;
  cam.file = path;
  auto require = [&](const char* key) {
    cv::FileNode node = fs[key];
    if (node.empty()) throw ConfigError(path, 0, key, "missing (expected as in OpenCV's calibration output)");
    return node;
  };
  cv::FileNode id = fs["camera_id"];
  cam.camera_id = id.isString() ? static_cast<std::string>(id) : std::filesystem::path(path).stem().string();

  cv::FileNode w = require("image_width"), h = require("image_height");
  if (!w.isInt() || static_cast<int>(w) <= 0)
    throw ConfigError(path, 0, "image_width", "expected a positive integer (pixels)");
  if (!h.isInt() || static_cast<int>(h) <= 0)
    throw ConfigError(path, 0, "image_height", "expected a positive integer (pixels)");
  cam.width_px = static_cast<int>(w);
  cam.height_px = static_cast<int>(h);

  cv::Mat K, D;
  try {
    require("camera_matrix") >> K;
    require("distortion_coefficients") >> D;
  } catch (const cv::Exception& e) {
    throw ConfigError(path, 0, "camera_matrix", std::string("expected an !!opencv-matrix: ") + e.err);
  }
  if (K.rows != 3 || K.cols != 3)
    throw ConfigError(path, 0, "camera_matrix", "is " + str(K.rows) + "x" + str(K.cols) + ", expected 3x3");
  K.convertTo(K, CV_64F);
  cam.fx_px = K.at<double>(0, 0);
  cam.fy_px = K.at<double>(1, 1);
  cam.cx_px = K.at<double>(0, 2);
  cam.cy_px = K.at<double>(1, 2);
  if (!(cam.fx_px > 0) || !(cam.fy_px > 0) || !std::isfinite(cam.fx_px) || !std::isfinite(cam.fy_px)) {
    throw ConfigError(path, 0, "camera_matrix",
                      "focal lengths fx=" + str(cam.fx_px) + ", fy=" + str(cam.fy_px) + " px, expected positive");
  }
  if (!(cam.cx_px >= -0.5 && cam.cx_px <= cam.width_px - 0.5 && cam.cy_px >= -0.5 && cam.cy_px <= cam.height_px - 0.5)) {
    throw ConfigError(path, 0, "camera_matrix",
                      "principal point (" + str(cam.cx_px) + ", " + str(cam.cy_px) + ") px lies outside the " +
                          str(cam.width_px) + "x" + str(cam.height_px) + " image");
  }
  D = D.reshape(1, 1);
  D.convertTo(D, CV_64F);
  const int n = D.cols;
  if (n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    throw ConfigError(path, 0, "distortion_coefficients",
                      "has " + str(n) + " entries, expected 4, 5, 8, 12 or 14 (OpenCV's models)");
  }
  for (int i = 0; i < n; ++i) {
    const double d = D.at<double>(0, i);
    if (!std::isfinite(d))
      throw ConfigError(path, 0, "distortion_coefficients[" + str(i) + "]", "is not finite");
    cam.distortion.push_back(d);
  }
  return cam;
}

}  // namespace arphys::config
