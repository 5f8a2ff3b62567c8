#pragma once
#include <vector>

#include <Eigen/Core>

#include "configs/loader/camera_config.hpp"

namespace arphys::rendering {

// OpenGL's projection for a calibrated pinhole camera, so that a point drawn at its pose
// lands on the pixel OpenCV's projection gives (pixel centres at integers, y down). GL
// draws pinhole; the camera's distortion is applied after drawing (LensWarp).
struct CameraProjection {
  int width_px = 0, height_px = 0;
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;
  double near_m = 0.01, far_m = 20.0;
  std::vector<double> distortion;  // OpenCV's k1 k2 p1 p2 [k3 ...]; empty or zeros: none

  static CameraProjection from_config(const config::CameraConfig& camera, double near_m = 0.01, double far_m = 20.0);
  // Clip-from-eye matrix (eye = OpenGL camera frame: x right, y up, looking down -z).
  Eigen::Matrix4f clip_from_eye() const;
  // Eye-from-camera: OpenCV's camera frame (x right, y down, z forward) to OpenGL's.
  static Eigen::Matrix4f eye_from_camera();
};

}  // namespace arphys::rendering
