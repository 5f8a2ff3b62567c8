#pragma once
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "configs/loader/camera_config.hpp"

namespace arphys::tracking {

// The calibrated camera in the form OpenCV's pose solvers take. Pixel convention:
// OpenCV's (the centre of the top-left pixel is (0, 0)).
struct CameraModel {
  int width_px = 0;
  int height_px = 0;
  cv::Matx33d K = cv::Matx33d::eye();
  cv::Mat distortion;  // 1xN CV_64F; empty when the lens has none

  static CameraModel from_config(const config::CameraConfig& camera);
  // Projects a point in the camera frame (z forward) to pixels, distortion included.
  Eigen::Vector2d project(const Eigen::Vector3d& p_C) const;
};

}  // namespace arphys::tracking
