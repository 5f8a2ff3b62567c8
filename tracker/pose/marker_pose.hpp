#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

#include "simulator/geometry/pose.hpp"
#include "tracker/detection/marker_detector.hpp"
#include "tracker/pose/camera_model.hpp"

namespace arphys::tracking {

using geometry::Pose;

// The four corners of a marker of side size_m in its own frame M (origin at the
// centre, x right, y up, z out of the face), in DetectedMarker's corner order.
std::array<Eigen::Vector3d, 4> marker_corners_M(double size_m);

// Both solutions of the planar-square PnP (OpenCV's IPPE_SQUARE), best first. A
// single marker seen almost frontally has two poses that explain its corners nearly
// equally well (tilted towards or away from the camera): keep both, decide later.
struct MarkerPoseSolutions {
  std::array<Pose, 2> X_CM;
  std::array<double, 2> rms_px{0, 0};  // RMS reprojection error of the 4 corners
  int count = 0;
  // Second error over the first (>= 1); near 1 means the corners cannot tell them apart.
  double ambiguity_ratio() const;
};

// Throws std::invalid_argument when size_m is not positive and finite.
MarkerPoseSolutions solve_marker_pose(const DetectedMarker& marker, double size_m, const CameraModel& camera);

// A pose fitted to many points (an object with markers on several faces, the table's
// corner markers), with its quality.
struct PoseFit {
  Pose X_CO = Pose::Identity();
  double rms_px = 0;
  // 1-sigma errors from the Gauss-Newton covariance (pixel noise estimated from the
  // residuals, floored at 0.05 px): position of O's origin in metres, rotation in radians.
  double position_sigma_m = 0;
  double rotation_sigma_rad = 0;
};

// RMS reprojection error of points p_O (object frame) seen at uv_px under X_CO.
// Points behind the camera count as 1e6 px.
double reprojection_rms_px(const std::vector<Eigen::Vector3d>& p_O, const std::vector<Eigen::Vector2d>& uv_px,
                           const Pose& X_CO, const CameraModel& camera);

// Levenberg-Marquardt refinement of X_CO_initial over all points jointly.
PoseFit refine_pose(const std::vector<Eigen::Vector3d>& p_O, const std::vector<Eigen::Vector2d>& uv_px,
                    const Pose& X_CO_initial, const CameraModel& camera);

}  // namespace arphys::tracking
