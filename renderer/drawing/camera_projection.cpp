#include "renderer/drawing/camera_projection.hpp"

#include <stdexcept>

namespace arphys::rendering {

CameraProjection CameraProjection::from_config(const config::CameraConfig& camera, double near_m, double far_m) {
  if (!(near_m > 0) || !(far_m > near_m)) {
    throw std::invalid_argument("camera projection: near " + std::to_string(near_m) + " m, far " +
                                std::to_string(far_m) + " m (expected 0 < near < far)");
  }
  CameraProjection p;
  p.width_px = camera.width_px;
  p.height_px = camera.height_px;
  p.fx_px = camera.fx_px;
  p.fy_px = camera.fy_px;
  p.cx_px = camera.cx_px;
  p.cy_px = camera.cy_px;
  p.near_m = near_m;
  p.far_m = far_m;
  if (camera.has_distortion()) p.distortion = camera.distortion;
  return p;
}

Eigen::Matrix4f CameraProjection::clip_from_eye() const {
  // Window x of OpenCV pixel u is u + 0.5 (GL samples pixel centres at half-integers);
  // window y counts from the bottom: H - (v + 0.5).
  const double W = width_px, H = height_px, n = near_m, f = far_m;
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2 * fx_px / W;
  P(0, 2) = 1 - 2 * (cx_px + 0.5) / W;
  P(1, 1) = 2 * fy_px / H;
  P(1, 2) = 2 * (cy_px + 0.5) / H - 1;
  P(2, 2) = -(f + n) / (f - n);
  P(2, 3) = -2 * f * n / (f - n);
  P(3, 2) = -1;
  return P.cast<float>();
}

Eigen::Matrix4f CameraProjection::eye_from_camera() {
  Eigen::Matrix4f M = Eigen::Matrix4f::Identity();
  M(1, 1) = -1;
  M(2, 2) = -1;
  return M;
}

}  // namespace arphys::rendering
