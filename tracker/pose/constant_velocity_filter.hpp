#pragma once
// A constant-velocity Kalman filter on SE(3), for poses that drive physics. A pushed
// virtual body takes on the speed of the real body pushing it, and that speed is the
// difference of consecutive poses: 1 mm of pose noise at 30 Hz makes a 0.5 m/s push peak
// 20-25 % too fast. The one-euro filter smooths a still marker but, by design, hardly a
// moving one; this filter models the motion (white-noise acceleration), so it smooths
// a steady motion without lag and pays with an overshoot when the motion stops short.
//
// Translation: per axis, state (position, velocity). Rotation: the orientation and the
// world-frame angular velocity, updated through the rotation vector of the residual
// (an error-state filter). The measurement noise it assumes is the configured one or,
// when the measurements scatter more about a steady motion, their estimate: configured
// for 1 mm and fed 5 mm, it followed the noise, and a pushed bunny was thrown at 3.3-4x
// the push in the evaluation's stability map (2.3-2.9x with the estimate).
// A measurement further from the prediction than the gate is one of two things. Alone,
// right after an accepted one (within max_coast_s), it is taken for an outlier: a
// single-marker pose flipped to its other solution for a frame, a misfit. It is dropped
// and counted, and the output is the prediction, so the flip never reaches the physics.
// A second in a row, or one after a longer gap, restarts the filter at the measurement:
// the object did jump (a re-acquired track), and that is a new start, not a velocity.
// A gap longer than max_gap_s restarts it too.
#include <algorithm>
#include <array>
#include <cmath>

#include "simulator/geometry/pose.hpp"

namespace arphys::tracking {

struct ConstantVelocityParams {
  // Measurement standard deviations: the least the filter assumes. When the measurements
  // scatter more (a far or small marker, a blurred frame), the filter sees it and
  // assumes that instead (see noise_window_frames).
  double position_noise_m = 1e-3;
  double rotation_noise_rad = 5e-3;
  // Spectral density of the white acceleration noise: larger follows changes of speed
  // sooner and smooths less. The defaults give the same tracking index for both parts.
  double acceleration_psd_m2_s3 = 0.005;
  double angular_acceleration_psd_rad2_s3 = 0.125;
  double gate_m = 0.05;
  double gate_rad = 0.35;
  double max_gap_s = 0.5;
  // A gated measurement up to this long after the last accepted one may be dropped as an
  // outlier; after longer, the prediction is too stale to overrule a measurement.
  double max_coast_s = 0.1;
  // How many measurements the running estimate of the measurement variance averages
  // over. In measurements, not seconds: a 5 Hz camera's velocity change at a start or a
  // stop would otherwise weigh six times a 30 Hz one's.
  double noise_window_frames = 30;
};

class ConstantVelocityPoseFilter {
 public:
  ConstantVelocityPoseFilter() = default;
  // Throws std::invalid_argument naming the parameter when one is not positive.
  explicit ConstantVelocityPoseFilter(const ConstantVelocityParams& params);
  // Filters the pose measured at t_s (seconds). The first call, a call whose time does
  // not increase, and a late or repeatedly gated measurement pass it through and
  // restart; a lone gated one is dropped and the prediction at t_s returned.
  geometry::Pose filter(const geometry::Pose& X_measured, double t_s);
  void reset() { initialised_ = false; }

  // Whether the last call dropped its measurement as an outlier (its output is a
  // prediction, not a measurement), and how many calls have.
  bool rejected_last() const { return rejected_last_; }
  long rejected_count() const { return rejected_count_; }

  // The measurement standard deviations the filter assumes now (the configured ones, or
  // more, as the measurements show).
  double position_noise_m() const {
    return std::sqrt(position_variance_.in_force(params_.position_noise_m * params_.position_noise_m));
  }
  double rotation_noise_rad() const {
    return std::sqrt(rotation_variance_.in_force(params_.rotation_noise_rad * params_.rotation_noise_rad));
  }

  // The filter's velocity estimates (zero before two measurements).
  const Eigen::Vector3d& velocity_m_s() const { return v_m_s_; }
  const Eigen::Vector3d& angular_velocity_rad_s() const { return w_rad_s_; }

 private:
  // Covariance of one axis: [position, velocity].
  struct AxisCovariance {
    double pp = 0, pv = 0, vv = 0;
    void predict(double dt_s, double psd);
    // Kalman gains for a measurement of the position with the given variance; updates
    // the covariance.
    Eigen::Vector2d update(double measurement_variance);
  };
  // A running estimate of one part's measurement variance (per axis), from the change
  // of its velocity between consecutive measurement intervals (an exponential mean,
  // weight alpha per measurement). Not from the filter's innovations: after a sudden
  // stop they stay large for several frames and the estimate rose with them (a 12.4 mm
  // overshoot against 7.4 over 40 noise draws); the velocity changes once.
  struct NoiseEstimate {
    double variance = 0;
    // The measurement variance to assume: the estimate, never below the configured one.
    double in_force(double floor_variance) const { return std::max(floor_variance, variance); }
    // Takes one velocity change in, with the measurement variance's factor in its
    // variance (1/s^2); returns the measurement variance to update with (never below
    // floor_variance).
    double observe(const Eigen::Vector3d& velocity_change, double spread_per_s2, double floor_variance, double alpha);
  };
  void restart(const geometry::Pose& X_measured, double t_s);

  ConstantVelocityParams params_;
  bool initialised_ = false;
  bool rejected_last_ = false;
  long rejected_count_ = 0;
  double t_last_s_ = 0;
  Eigen::Vector3d p_m_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_m_s_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_rad_s_ = Eigen::Vector3d::Zero();
  AxisCovariance translation_, rotation_;
  // Kept across restarts: how noisy the measurements are belongs to the camera and the
  // marker, not to the track.
  NoiseEstimate position_variance_, rotation_variance_;
  // The last accepted measurements since the (re)start, oldest first.
  struct TimedPose {
    double t_s = 0;
    geometry::Pose X = geometry::Pose::Identity();
  };
  std::array<TimedPose, 2> history_;
  int history_size_ = 0;
};

}  // namespace arphys::tracking
