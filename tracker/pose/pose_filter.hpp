#pragma once
#include <string>

#include "simulator/geometry/pose.hpp"
#include "tracker/pose/constant_velocity_filter.hpp"

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

// The pose filter an object track runs: none, one-euro (steadies a still marker, for
// the overlay) or constant-velocity (smooths a moving one, for physics; see
// constant_velocity_filter.hpp).
enum class PoseFilterKind { kNone, kOneEuro, kConstantVelocity };
const char* to_string(PoseFilterKind kind);
// "none" | "one_euro" | "constant_velocity"; throws std::invalid_argument naming the value.
PoseFilterKind pose_filter_kind_from(const std::string& name);

struct PoseFilterSpec {
  PoseFilterKind kind = PoseFilterKind::kNone;
  OneEuroParams one_euro;
  ConstantVelocityParams constant_velocity;
};

class PoseFilter {
 public:
  PoseFilter() = default;
  explicit PoseFilter(const PoseFilterSpec& spec)
      : kind_(spec.kind), one_euro_(spec.one_euro), constant_velocity_(spec.constant_velocity) {}
  Pose filter(const Pose& X_measured, double t_s);
  // The last call dropped its measurement as an outlier and returned a prediction (the
  // constant-velocity filter's gate; the others never drop one).
  bool rejected_last() const { return kind_ == PoseFilterKind::kConstantVelocity && constant_velocity_.rejected_last(); }
  void reset() {
    one_euro_.reset();
    constant_velocity_.reset();
  }

 private:
  PoseFilterKind kind_ = PoseFilterKind::kNone;
  OneEuroPoseFilter one_euro_;
  ConstantVelocityPoseFilter constant_velocity_;
};

}  // namespace arphys::tracking
