#include "tracker/pose/pose_filter.hpp"

#include <cmath>
#include <stdexcept>

namespace arphys::tracking {

namespace {

// Smoothing factor of a first-order low-pass with the given cutoff over dt.
double smoothing(double cutoff_hz, double dt_s) {
  const double tau = 1.0 / (2.0 * M_PI * cutoff_hz);
  return 1.0 / (1.0 + tau / dt_s);
}

}  // namespace

Pose OneEuroPoseFilter::filter(const Pose& X_measured, double t_s) {
  const double dt = t_s - t_last_s_;
  if (!initialised_ || !(dt > 0)) {
    initialised_ = true;
    t_last_s_ = t_s;
    X_last_ = X_measured;
    position_speed_m_s_ = rotation_speed_rad_s_ = 0;
    return X_measured;
  }
  const Eigen::Vector3d dp = X_measured.translation() - X_last_.translation();
  const Eigen::AngleAxisd dR(X_last_.linear().transpose() * X_measured.linear());
  const Eigen::Vector3d dr = dR.angle() * dR.axis();

  const double a_d = smoothing(params_.derivative_cutoff_hz, dt);
  position_speed_m_s_ += a_d * (dp.norm() / dt - position_speed_m_s_);
  rotation_speed_rad_s_ += a_d * (dr.norm() / dt - rotation_speed_rad_s_);

  const double a_p = smoothing(params_.min_cutoff_hz + params_.beta_position_s_m * position_speed_m_s_, dt);
  const double a_r = smoothing(params_.min_cutoff_hz + params_.beta_rotation_s_rad * rotation_speed_rad_s_, dt);
  Pose X = Pose::Identity();
  X.translation() = X_last_.translation() + a_p * dp;
  const double angle = a_r * dr.norm();
  X.linear() = angle > 0 ? Eigen::Matrix3d(X_last_.linear() * Eigen::AngleAxisd(angle, dr.normalized()).toRotationMatrix())
                         : X_last_.linear();
  X_last_ = X;
  t_last_s_ = t_s;
  return X;
}

const char* to_string(PoseFilterKind kind) {
  switch (kind) {
    case PoseFilterKind::kOneEuro: return "one_euro";
    case PoseFilterKind::kConstantVelocity: return "constant_velocity";
    case PoseFilterKind::kNone: break;
  }
  return "none";
}

PoseFilterKind pose_filter_kind_from(const std::string& name) {
  for (PoseFilterKind kind : {PoseFilterKind::kNone, PoseFilterKind::kOneEuro, PoseFilterKind::kConstantVelocity})
    if (name == to_string(kind)) return kind;
  throw std::invalid_argument("pose filter '" + name + "': expected none, one_euro or constant_velocity");
}

Pose PoseFilter::filter(const Pose& X_measured, double t_s) {
  switch (kind_) {
    case PoseFilterKind::kOneEuro: return one_euro_.filter(X_measured, t_s);
    case PoseFilterKind::kConstantVelocity: return constant_velocity_.filter(X_measured, t_s);
    case PoseFilterKind::kNone: break;
  }
  return X_measured;
}

}  // namespace arphys::tracking
