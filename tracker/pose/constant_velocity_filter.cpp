#include "tracker/pose/constant_velocity_filter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace arphys::tracking {

namespace {

void require_positive(double value, const char* name) {
  if (!(value > 0) || !std::isfinite(value))
    throw std::invalid_argument(std::string("ConstantVelocityParams.") + name + " must be positive and finite, got " +
                                std::to_string(value));
}

Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& r) {
  const double angle = r.norm();
  return angle > 0 ? Eigen::AngleAxisd(angle, r / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

// The initial velocity variance: nothing is known about the speed of a new track.
constexpr double kUnknownSpeedVariance = 1.0;

}  // namespace

ConstantVelocityPoseFilter::ConstantVelocityPoseFilter(const ConstantVelocityParams& params) : params_(params) {
  require_positive(params.position_noise_m, "position_noise_m");
  require_positive(params.rotation_noise_rad, "rotation_noise_rad");
  require_positive(params.acceleration_psd_m2_s3, "acceleration_psd_m2_s3");
  require_positive(params.angular_acceleration_psd_rad2_s3, "angular_acceleration_psd_rad2_s3");
  require_positive(params.gate_m, "gate_m");
  require_positive(params.gate_rad, "gate_rad");
  require_positive(params.max_gap_s, "max_gap_s");
  require_positive(params.max_coast_s, "max_coast_s");
  if (!(params.noise_window_frames >= 1) || !std::isfinite(params.noise_window_frames))
    throw std::invalid_argument("ConstantVelocityParams.noise_window_frames must be at least 1, got " +
                                std::to_string(params.noise_window_frames));
}

void ConstantVelocityPoseFilter::AxisCovariance::predict(double dt, double psd) {
  // P <- F P F^T + Q for F = [1 dt; 0 1], Q = psd [dt^3/3 dt^2/2; dt^2/2 dt].
  pp += 2 * dt * pv + dt * dt * vv + psd * dt * dt * dt / 3;
  pv += dt * vv + psd * dt * dt / 2;
  vv += psd * dt;
}

Eigen::Vector2d ConstantVelocityPoseFilter::AxisCovariance::update(double r) {
  const double s = pp + r;
  const Eigen::Vector2d gain(pp / s, pv / s);
  // P <- (I - K H) P with H = [1 0].
  const double pp_new = (1 - gain[0]) * pp;
  const double pv_new = (1 - gain[0]) * pv;
  const double vv_new = vv - gain[1] * pv;
  pp = pp_new;
  pv = pv_new;
  vv = vv_new;
  return gain;
}

double ConstantVelocityPoseFilter::NoiseEstimate::observe(const Eigen::Vector3d& velocity_change, double spread_per_s2,
                                                          double floor_variance, double alpha) {
  const double in_force = this->in_force(floor_variance);
  // A sample is clipped at 3 sigma: a sudden stop is one large velocity change, the
  // motion's and not the noise's, and may not raise the estimate much.
  const double per_axis = std::min(velocity_change.squaredNorm() / 3 / spread_per_s2, 9 * in_force);
  variance += alpha * (per_axis - variance);
  return this->in_force(floor_variance);
}

void ConstantVelocityPoseFilter::restart(const geometry::Pose& X, double t_s) {
  initialised_ = true;
  rejected_last_ = false;
  history_ = {{{t_s, X}}};
  history_size_ = 1;
  t_last_s_ = t_s;
  p_m_ = X.translation();
  R_ = X.linear();
  v_m_s_.setZero();
  w_rad_s_.setZero();
  translation_ = {params_.position_noise_m * params_.position_noise_m, 0, kUnknownSpeedVariance};
  rotation_ = {params_.rotation_noise_rad * params_.rotation_noise_rad, 0, kUnknownSpeedVariance};
}

geometry::Pose ConstantVelocityPoseFilter::filter(const geometry::Pose& X_measured, double t_s) {
  const double dt = t_s - t_last_s_;
  const bool after_rejection = rejected_last_;
  rejected_last_ = false;
  if (!initialised_ || !(dt > 0) || dt > params_.max_gap_s) {
    restart(X_measured, t_s);
    return X_measured;
  }
  // Predict.
  const Eigen::Vector3d p_predicted = p_m_ + dt * v_m_s_;
  const Eigen::Matrix3d R_predicted = rotation_from_vector(dt * w_rad_s_) * R_;
  const Eigen::Vector3d dp = X_measured.translation() - p_predicted;
  const Eigen::Vector3d dr = rotation_vector(X_measured.linear() * R_predicted.transpose());
  if (dp.norm() > params_.gate_m || dr.norm() > params_.gate_rad) {
    if (after_rejection || dt > params_.max_coast_s) {
      restart(X_measured, t_s);
      return X_measured;
    }
    // The state stays at the last accepted measurement: the next one is predicted from there.
    rejected_last_ = true;
    ++rejected_count_;
    geometry::Pose X = geometry::Pose::Identity();
    X.translation() = p_predicted;
    X.linear() = R_predicted;
    return X;
  }
  translation_.predict(dt, params_.acceleration_psd_m2_s3);
  rotation_.predict(dt, params_.angular_acceleration_psd_rad2_s3);
  // Update, with the measurement variance the last three measurements show.
  double position_variance = params_.position_noise_m * params_.position_noise_m;
  double rotation_variance = params_.rotation_noise_rad * params_.rotation_noise_rad;
  if (history_size_ == 2) {
    // The change of the velocity between the last two measurement intervals: zero for a
    // steady motion, so its scatter is the measurements' (measurement variance times
    // spread, per axis).
    const auto& [t0, X0] = history_[0];
    const auto& [t1, X1] = history_[1];
    const double dt0 = t1 - t0, dt1 = t_s - t1;
    const double spread = 1 / (dt0 * dt0) + std::pow(1 / dt0 + 1 / dt1, 2) + 1 / (dt1 * dt1);
    const Eigen::Vector3d dv = (X_measured.translation() - X1.translation()) / dt1 - (X1.translation() - X0.translation()) / dt0;
    const Eigen::Vector3d dw = rotation_vector(X_measured.linear() * X1.linear().transpose()) / dt1 -
                               rotation_vector(X1.linear() * X0.linear().transpose()) / dt0;
    const double alpha = 1.0 / params_.noise_window_frames;
    position_variance = position_variance_.observe(dv, spread, position_variance, alpha);
    rotation_variance = rotation_variance_.observe(dw, spread, rotation_variance, alpha);
    history_[0] = history_[1];
  }
  history_[history_size_ == 2 ? 1 : history_size_++] = {t_s, X_measured};
  const Eigen::Vector2d kt = translation_.update(position_variance);
  const Eigen::Vector2d kr = rotation_.update(rotation_variance);
  p_m_ = p_predicted + kt[0] * dp;
  v_m_s_ += kt[1] * dp;
  // Renormalised, so that many products of rotations stay a rotation.
  R_ = Eigen::Quaterniond(rotation_from_vector(kr[0] * dr) * R_predicted).normalized().toRotationMatrix();
  w_rad_s_ += kr[1] * dr;
  t_last_s_ = t_s;

  geometry::Pose X = geometry::Pose::Identity();
  X.translation() = p_m_;
  X.linear() = R_;
  return X;
}

}  // namespace arphys::tracking
