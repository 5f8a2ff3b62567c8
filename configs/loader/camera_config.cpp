#include "configs/loader/camera_config.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "configs/loader/config_error.hpp"
#include "configs/loader/yaml_reader.hpp"

namespace arphys::config {

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

// An OpenCV `!!opencv-matrix` node (rows, cols, dt, data) as row-major values, its size
// checked before anything is allocated.
std::vector<double> matrix(const Reader& r, const YAML::Node& node, const std::string& key, int* rows, int* cols) {
  r.only_keys(node, key, {"rows", "cols", "dt", "data"});
  *rows = r.integer(r.required(node, key, "rows"), key + ".rows", "an integer from 1 to 16");
  *cols = r.integer(r.required(node, key, "cols"), key + ".cols", "an integer from 1 to 16");
  if (*rows < 1 || *rows > 16 || *cols < 1 || *cols > 16) {
    r.fail(node, key, str(*rows) + "x" + str(*cols) + ", expected 1 to 16 rows and columns");
  }
  const YAML::Node data = r.required(node, key, "data");
  if (!data.IsSequence() || static_cast<int>(data.size()) != *rows * *cols) {
    r.fail(data, key + ".data", "expected a list of rows x cols = " + str(*rows * *cols) + " numbers");
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < data.size(); ++i) values.push_back(r.number(data[i], key + ".data[" + str(i) + "]"));
  return values;
}

CameraConfig load_camera_checked(const std::string& path) {
  std::error_code fs_error;
  if (!std::filesystem::is_regular_file(path, fs_error)) {
    throw ConfigError(path, 0, "", "camera file does not exist (expected an OpenCV calibration YAML file)");
  }
  // OpenCV writes YAML 1.0 with a "%YAML:1.0" directive line that YAML 1.2 parsers
  // refuse: it is dropped (a blank line keeps the line numbers). yaml-cpp instead of
  // cv::FileStorage: OpenCV 4.6's parser loops forever on some damaged files (fuzzing).
  std::ifstream in(path);
  std::stringstream text;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    text << (first && line.rfind("%YAML", 0) == 0 ? "" : line) << "\n";
    first = false;
  }
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", "not valid YAML: " + e.msg);
  }
  Reader r(path, std::filesystem::path(path).parent_path());
  r.only_keys(root, "", {"camera_id", "image_width", "image_height", "camera_matrix", "distortion_coefficients",
                         "calibration_time", "avg_reprojection_error", "nr_of_frames", "flags"});
  CameraConfig cam;
  cam.file = path;
  cam.camera_id = root["camera_id"].IsDefined() ? r.string(root["camera_id"], "camera_id")
                                                : std::filesystem::path(path).stem().string();
  cam.width_px = r.integer(r.required(root, "", "image_width"), "image_width", "a positive integer (pixels)");
  cam.height_px = r.integer(r.required(root, "", "image_height"), "image_height", "a positive integer (pixels)");
  if (cam.width_px <= 0 || cam.width_px > 16384) {
    r.fail(root["image_width"], "image_width", "expected a positive integer (pixels, at most 16384)");
  }
  if (cam.height_px <= 0 || cam.height_px > 16384) {
    r.fail(root["image_height"], "image_height", "expected a positive integer (pixels, at most 16384)");
  }

  int rows = 0, cols = 0;
  const std::vector<double> K = matrix(r, r.required(root, "", "camera_matrix"), "camera_matrix", &rows, &cols);
  if (rows != 3 || cols != 3) r.fail(root["camera_matrix"], "camera_matrix", "is " + str(rows) + "x" + str(cols) + ", expected 3x3");
  cam.fx_px = K[0];
  cam.fy_px = K[4];
  cam.cx_px = K[2];
  cam.cy_px = K[5];
  if (!(cam.fx_px > 0) || !(cam.fy_px > 0)) {
    r.fail(root["camera_matrix"], "camera_matrix",
           "focal lengths fx=" + str(cam.fx_px) + ", fy=" + str(cam.fy_px) + " px, expected positive");
  }
  if (!(cam.cx_px >= -0.5 && cam.cx_px <= cam.width_px - 0.5 && cam.cy_px >= -0.5 && cam.cy_px <= cam.height_px - 0.5)) {
    r.fail(root["camera_matrix"], "camera_matrix",
           "principal point (" + str(cam.cx_px) + ", " + str(cam.cy_px) + ") px lies outside the " + str(cam.width_px) +
               "x" + str(cam.height_px) + " image");
  }
  const std::vector<double> D =
      matrix(r, r.required(root, "", "distortion_coefficients"), "distortion_coefficients", &rows, &cols);
  const std::size_t n = D.size();
  if ((rows != 1 && cols != 1) || (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)) {
    r.fail(root["distortion_coefficients"], "distortion_coefficients",
           "has " + str(n) + " entries, expected 4, 5, 8, 12 or 14 (OpenCV's models, as a row or a column)");
  }
  cam.distortion = D;
  return cam;
}

}  // namespace

CameraConfig load_camera(const std::string& path) {
  try {
    return load_camera_checked(path);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", std::string("unreadable YAML: ") + e.msg);
  }
}

}  // namespace arphys::config
