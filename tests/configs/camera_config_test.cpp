#include "configs/loader/camera_config.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "configs/loader/config_error.hpp"

namespace arphys::config {
namespace {

const std::string kCameras = std::string(ARPHYS_SOURCE_DIR) + "/configs/cameras/";

TEST(CameraConfig, SyntheticCameraLoads) {
  const CameraConfig cam = load_camera(kCameras + "synthetic_640x480.yaml");
  EXPECT_EQ(cam.camera_id, "synthetic");
  EXPECT_EQ(cam.width_px, 640);
  EXPECT_EQ(cam.height_px, 480);
  EXPECT_NEAR(cam.fx_px, 554.2562584220407, 1e-12);
  EXPECT_DOUBLE_EQ(cam.cx_px, 319.5);
  // 60 degree horizontal field of view: fx = (640/2) / tan(30 deg).
  EXPECT_NEAR(2 * std::atan(320.0 / cam.fx_px), M_PI / 3, 1e-12);
  EXPECT_FALSE(cam.has_distortion());
  EXPECT_EQ(cam.distortion.size(), 5u);
}

TEST(CameraConfig, ExampleWebcamHasDistortion) {
  const CameraConfig cam = load_camera(kCameras + "webcam_640x480_example.yaml");
  EXPECT_TRUE(cam.has_distortion());
  EXPECT_NEAR(cam.distortion[1], -0.1934, 1e-12);
}

std::string error_of(const std::string& body) {
  const std::string path = ::testing::TempDir() + "camera_" + std::to_string(std::hash<std::string>{}(body)) + ".yaml";
  std::ofstream(path) << "%YAML:1.0\n---\n" << body;
  std::string message;
  try {
    load_camera(path);
    ADD_FAILURE() << "camera loaded";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    message = e.what();
  }
  std::remove(path.c_str());  // one name per body: it would otherwise pile up in TempDir
  return message;
}

const char* kMatrix = "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ %s ]\n";

std::string with_matrix(const std::string& k, const std::string& extra) {
  char text[512];
  std::snprintf(text, sizeof text, kMatrix, k.c_str());
  return "image_width: 640\nimage_height: 480\n" + std::string(text) + extra;
}

const std::string kDist5 = "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [0, 0, 0, 0, 0]\n";

TEST(CameraConfig, BadValuesNameTheKey) {
  EXPECT_NE(error_of(with_matrix("-500, 0, 320, 0, 500, 240, 0, 0, 1", kDist5)).find("camera_matrix: focal lengths fx=-500"),
            std::string::npos);
  EXPECT_NE(error_of(with_matrix("500, 0, 900, 0, 500, 240, 0, 0, 1", kDist5)).find("principal point (900, 240)"),
            std::string::npos);
  EXPECT_NE(error_of(with_matrix("500, 0, 320, 0, 500, 240, 0, 0, 1", "")).find("distortion_coefficients: missing"),
            std::string::npos);
  const std::string dist3 = "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   data: [0, 0, 0]\n";
  EXPECT_NE(error_of(with_matrix("500, 0, 320, 0, 500, 240, 0, 0, 1", dist3)).find("has 3 entries, expected 4, 5, 8, 12 or 14"),
            std::string::npos);
  EXPECT_NE(error_of("image_width: -3\nimage_height: 480\n").find("image_width: expected a positive integer"), std::string::npos);
  EXPECT_NE(error_of("image_width: [unclosed\n").find("not valid YAML"), std::string::npos);
}

TEST(CameraConfig, MissingFile) {
  try {
    load_camera("/no/such/camera.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such/camera.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace arphys::config
