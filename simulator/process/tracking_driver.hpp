#pragma once
// Turns tracked poses of a real object (timestamped by camera capture) into the
// trajectory its kinematic body follows, under an explicit latency policy:
//   kDelay:        each pose is reached one frame interval after its capture, moving on
//                  the screw from the previous one: smooth, continuous, one frame late.
//   kExtrapolate:  the body continues with the last measured twist; when a new pose
//                  arrives it blends to it over half a frame, then extrapolates again:
//                  no added latency, small corrections.
// A lost track, or no pose for longer than the stale timeout, holds the body still.
// Every new pose under kDelay (a pose that flipped to the other solution of a single
// marker, say) is reached no faster than a hand moves a real object (max_speed_m_s,
// max_rate_rad_s) instead of in one frame, so the body does not strike virtual bodies
// at many m/s. kExtrapolate follows the measured twist as it is.
// A track re-acquired further on (either policy) catches up at catch_up_factor times
// the speed the object itself made over the gap (within those limits): a box pushing a
// bunny at 0.25 m/s, lost for 0.3 s, caught up at the hand's 1.5 m/s and threw the bunny
// at 7x; at twice its own speed it pushes the bunny on as the real box did, and closes
// the gap in about the time it lasted. While the body lags behind, each new pose is
// headed for from where the body is, not queued behind the one it has not reached: the
// body catches up with the live pose, not with a backlog of old ones.
#include <cstdint>
#include <string>

#include "simulator/dynamics/kinematic_trajectory.hpp"

namespace arphys::sim {

enum class TrackingPolicy { kDelay, kExtrapolate };
const char* to_string(TrackingPolicy policy);
TrackingPolicy tracking_policy_from(const std::string& name);  // "delay" | "extrapolate"

// How fast the driven body may go where the tracking would jump (see above).
struct DriverLimits {
  double max_speed_m_s = 1.5;
  double max_rate_rad_s = 2 * 3.141592653589793;
  double catch_up_factor = 2.0;  // at least 1
};

class TrackingDriver {
 public:
  // Throws std::invalid_argument naming the limit that is not positive (or, for the
  // catch-up factor, below 1).
  TrackingDriver(TrackingPolicy policy, const DriverLimits& limits = {}, double default_frame_interval_s = 1.0 / 30);

  // A measured pose captured at simulation time capture_t_s (must increase; the
  // caller checks). now_s: the current simulation time.
  void on_pose(double capture_t_s, const geometry::Pose& X_WO, double now_s);
  // The object is not seen any more (status LOST, or stale): hold it where it is.
  void on_lost(double now_s);
  // Holds the body at X_WO from t_s until a pose arrives, which it then reaches as a
  // re-acquired track (within the speed limits) instead of appearing there: a restarted
  // simulator knows where the body was.
  void hold_at(double t_s, const geometry::Pose& X_WO);

  // The simulation clock moved by by_s against capture times (SimulatorCore::drop_time):
  // every pose, and the last capture, is timed by_s later.
  void shift_time(double by_s);

  const dynamics::KinematicTrajectory& trajectory() const { return trajectory_; }
  bool has_pose() const { return !trajectory_.empty(); }
  double last_capture_s() const { return last_capture_s_; }  // meaningless before the first pose
  // Added latency of the policy, seconds (one frame interval for kDelay, 0 otherwise).
  double added_latency_s() const { return policy_ == TrackingPolicy::kDelay ? frame_interval_s_ : 0.0; }

 private:
  // The earliest time the body may reach `to` when it leaves `from` at t_s, within the
  // limits in force.
  double earliest_arrival(double t_s, const geometry::Pose& from, const geometry::Pose& to) const;
  // Re-acquired at `to` gap_s after the last capture (0: unknown), the body at `from`:
  // the limits of the catch-up.
  void limit_catch_up(const geometry::Pose& from, const geometry::Pose& to, double gap_s);

  TrackingPolicy policy_;
  double max_speed_m_s_, max_rate_rad_s_, catch_up_factor_;
  double speed_limit_m_s_, rate_limit_rad_s_;  // in force: the maxima, or a catch-up's
  bool lagging_ = false;  // the last pose is reached later than its capture asks (kDelay)
  dynamics::KinematicTrajectory trajectory_;
  double frame_interval_s_;
  double last_capture_s_ = 0;
  bool captured_ = false;  // a pose has come
  geometry::Pose last_pose_ = geometry::Pose::Identity();
  bool lost_ = true;
};

}  // namespace arphys::sim
