#include "tracker/pose/camera_model.hpp"

#include <opencv2/calib3d.hpp>

namespace arphys::tracking {

CameraModel CameraModel::from_config(const config::CameraConfig& camera) {
  CameraModel model;
  model.width_px = camera.width_px;
  model.height_px = camera.height_px;
  model.K = cv::Matx33d(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  if (camera.has_distortion()) model.distortion = cv::Mat(camera.distortion, true).reshape(1, 1);
  return model;
}

Eigen::Vector2d CameraModel::project(const Eigen::Vector3d& p_C) const {
  std::vector<cv::Point3d> object{{p_C.x(), p_C.y(), p_C.z()}};
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, distortion, image);
  return {image[0].x, image[0].y};
}

}  // namespace arphys::tracking
