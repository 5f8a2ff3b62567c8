#pragma once
#include "simulator/geometry/pose.hpp"

namespace arphys::tracking {

using geometry::Pose;

// The one-euro filter (Casiez, Roussel & Vogel, CHI 2012) on SE(3): a first-order
// low-pass whose cutoff rises with speed, so a still marker stops jittering and a moving
// one lags little. Translation and rotation (as the rotation vector of the step from the
// last output) are filtered separately, each with its own speed coefficient.
struct OneEuroParams {
  double min_cutoff_hz = 1.5;        // cutoff at rest: lower = steadier, more lag
  double beta_position_s_m = 20.0;   // cutoff increase per m/s of speed
  double beta_rotation_s_rad = 2.0;  // cutoff increase per rad/s
  double derivative_cutoff_hz = 1.0;
};

class OneEuroPoseFilter {
 public:
  OneEuroPoseFilter() = default;
  explicit OneEuroPoseFilter(const OneEuroParams& params) : params_(params) {}
  // Filters the pose measured at t_s (seconds, increasing). The first call, and any call
  // whose time does not increase, passes the measurement through and restarts.
  Pose filter(const Pose& X_measured, double t_s);
  void reset() { initialised_ = false; }

 private:
  OneEuroParams params_;
  bool initialised_ = false;
  double t_last_s_ = 0;
  Pose X_last_ = Pose::Identity();
  double position_speed_m_s_ = 0;
  double rotation_speed_rad_s_ = 0;
};

}  // namespace arphys::tracking
