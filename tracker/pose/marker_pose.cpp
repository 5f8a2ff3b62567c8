#include "tracker/pose/marker_pose.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace arphys::tracking {

namespace {

Pose pose_from_rt(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R;
  cv::cv2eigen(R_cv, R);
  Pose X = Pose::Identity();
  X.linear() = R;
  X.translation() = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return X;
}

void rt_from_pose(const Pose& X, cv::Mat& rvec, cv::Mat& tvec) {
  cv::Mat R_cv;
  const Eigen::Matrix3d R = X.linear();
  cv::eigen2cv(R, R_cv);
  cv::Rodrigues(R_cv, rvec);
  tvec = (cv::Mat_<double>(3, 1) << X.translation().x(), X.translation().y(), X.translation().z());
}

}  // namespace

std::array<Eigen::Vector3d, 4> marker_corners_M(double size_m) {
  const double h = size_m / 2;
  return {Eigen::Vector3d(-h, -h, 0), Eigen::Vector3d(h, -h, 0), Eigen::Vector3d(h, h, 0), Eigen::Vector3d(-h, h, 0)};
}

double MarkerPoseSolutions::ambiguity_ratio() const {
  if (count < 2) return 1e9;
  return rms_px[1] / std::max(rms_px[0], 1e-9);
}

MarkerPoseSolutions solve_marker_pose(const DetectedMarker& marker, double size_m, const CameraModel& camera) {
  if (!(size_m > 0) || !std::isfinite(size_m)) {
    throw std::invalid_argument("solve_marker_pose: marker size_m = " + std::to_string(size_m) +
                                " (expected a positive side length in metres)");
  }
  // IPPE_SQUARE wants the corners in the order top-left, top-right, bottom-right,
  // bottom-left with the object points below (its documented contract).
  const double h = size_m / 2;
  const std::vector<cv::Point3d> object{{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  std::vector<cv::Point2d> image;
  for (int k : {3, 2, 1, 0}) image.emplace_back(marker.corners_px[k].x(), marker.corners_px[k].y());
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat errors;
  cv::solvePnPGeneric(object, image, camera.K, camera.distortion, rvecs, tvecs, false, cv::SOLVEPNP_IPPE_SQUARE,
                      cv::noArray(), cv::noArray(), errors);
  MarkerPoseSolutions solutions;
  cv::Mat errors64;
  if (!errors.empty()) errors.convertTo(errors64, CV_64F);  // OpenCV may hand back CV_32F
  solutions.count = std::min<int>(2, static_cast<int>(rvecs.size()));
  for (int i = 0; i < solutions.count; ++i) {
    cv::Mat r, t;
    rvecs[i].convertTo(r, CV_64F);
    tvecs[i].convertTo(t, CV_64F);
    solutions.X_CM[i] = pose_from_rt(r, t);
    solutions.rms_px[i] = errors64.empty() ? 0 : errors64.at<double>(i);
  }
  return solutions;
}

double reprojection_rms_px(const std::vector<Eigen::Vector3d>& p_O, const std::vector<Eigen::Vector2d>& uv_px,
                           const Pose& X_CO, const CameraModel& camera) {
  if (p_O.empty()) return 0;
  std::vector<cv::Point3d> object;
  object.reserve(p_O.size());
  for (const auto& p : p_O) {
    const Eigen::Vector3d q = X_CO * p;
    if (q.z() <= 1e-6) return 1e6;
    object.emplace_back(q.x(), q.y(), q.z());
  }
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera.K, camera.distortion, image);
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    sum += (Eigen::Vector2d(image[i].x, image[i].y) - uv_px[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(image.size()));
}

PoseFit refine_pose(const std::vector<Eigen::Vector3d>& p_O, const std::vector<Eigen::Vector2d>& uv_px,
                    const Pose& X_CO_initial, const CameraModel& camera) {
  if (p_O.size() != uv_px.size() || p_O.size() < 3) {
    throw std::invalid_argument("refine_pose: needs >= 3 point pairs, got " + std::to_string(p_O.size()) + " and " +
                                std::to_string(uv_px.size()));
  }
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (size_t i = 0; i < p_O.size(); ++i) {
    object.emplace_back(p_O[i].x(), p_O[i].y(), p_O[i].z());
    image.emplace_back(uv_px[i].x(), uv_px[i].y());
  }
  cv::Mat rvec, tvec;
  rt_from_pose(X_CO_initial, rvec, tvec);
  cv::solvePnPRefineLM(object, image, camera.K, camera.distortion, rvec, tvec,
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 1e-10));
  PoseFit fit;
  fit.X_CO = pose_from_rt(rvec, tvec);

  // Covariance of (rvec, tvec) from the projection Jacobian at the optimum.
  std::vector<cv::Point2d> projected;
  cv::Mat jacobian;
  cv::projectPoints(object, rvec, tvec, camera.K, camera.distortion, projected, jacobian);
  double sse = 0;
  for (size_t i = 0; i < projected.size(); ++i) {
    sse += (Eigen::Vector2d(projected[i].x, projected[i].y) - uv_px[i]).squaredNorm();
  }
  const double n = static_cast<double>(projected.size());
  fit.rms_px = std::sqrt(sse / n);
  const double dof = std::max(1.0, 2 * n - 6);
  const double sigma_px = std::max(0.05, std::sqrt(sse / dof));
  Eigen::MatrixXd J;
  cv::cv2eigen(jacobian.colRange(0, 6), J);
  const Eigen::Matrix<double, 6, 6> JtJ = J.transpose() * J;
  const Eigen::Matrix<double, 6, 6> covariance = sigma_px * sigma_px * JtJ.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
  fit.rotation_sigma_rad = std::sqrt(std::max(0.0, covariance.topLeftCorner<3, 3>().trace()));
  fit.position_sigma_m = std::sqrt(std::max(0.0, covariance.bottomRightCorner<3, 3>().trace()));
  return fit;
}

}  // namespace arphys::tracking
