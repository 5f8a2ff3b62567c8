#include "simulator/process/tracking_driver.hpp"

#include <algorithm>
#include <stdexcept>

#include "simulator/geometry/screw_motion.hpp"

namespace arphys::sim {

const char* to_string(TrackingPolicy policy) { return policy == TrackingPolicy::kDelay ? "delay" : "extrapolate"; }

TrackingPolicy tracking_policy_from(const std::string& name) {
  if (name == "delay") return TrackingPolicy::kDelay;
  if (name == "extrapolate") return TrackingPolicy::kExtrapolate;
  throw std::invalid_argument("tracking policy '" + name + "': expected 'delay' or 'extrapolate'");
}

namespace {

double distance_m(const geometry::Pose& from, const geometry::Pose& to) {
  return (to.translation() - from.translation()).norm();
}
double angle_rad(const geometry::Pose& from, const geometry::Pose& to) {
  return Eigen::AngleAxisd(from.linear().transpose() * to.linear()).angle();
}

// A catch-up never crawls: an object seen still across a gap, yet a few mm off, is
// reached at these speeds (a gentle push, a tenth of the hand's limits).
constexpr double kMinCatchUpSpeed_m_s = 0.1;
constexpr double kMinCatchUpRate_rad_s = 0.5;

}  // namespace

TrackingDriver::TrackingDriver(TrackingPolicy policy, const DriverLimits& limits, double default_frame_interval_s)
    : policy_(policy), max_speed_m_s_(limits.max_speed_m_s), max_rate_rad_s_(limits.max_rate_rad_s),
      catch_up_factor_(limits.catch_up_factor), speed_limit_m_s_(limits.max_speed_m_s),
      rate_limit_rad_s_(limits.max_rate_rad_s), frame_interval_s_(default_frame_interval_s) {
  if (!(max_speed_m_s_ > 0) || !(max_rate_rad_s_ > 0)) {
    throw std::invalid_argument("TrackingDriver: speed limits must be positive, got max_speed_m_s " +
                                std::to_string(max_speed_m_s_) + " and max_rate_rad_s " + std::to_string(max_rate_rad_s_));
  }
  if (!(catch_up_factor_ >= 1)) {
    throw std::invalid_argument("TrackingDriver: catch_up_factor must be at least 1 (or the body never catches up), got " +
                                std::to_string(catch_up_factor_));
  }
}

double TrackingDriver::earliest_arrival(double t_s, const geometry::Pose& from, const geometry::Pose& to) const {
  return t_s + std::max(distance_m(from, to) / speed_limit_m_s_, angle_rad(from, to) / rate_limit_rad_s_);
}

void TrackingDriver::limit_catch_up(const geometry::Pose& from, const geometry::Pose& to, double gap_s) {
  speed_limit_m_s_ = max_speed_m_s_;
  rate_limit_rad_s_ = max_rate_rad_s_;
  if (!(gap_s > 0)) return;  // how fast the object went is unknown: the hand's limits
  speed_limit_m_s_ = std::clamp(catch_up_factor_ * distance_m(from, to) / gap_s, kMinCatchUpSpeed_m_s, max_speed_m_s_);
  rate_limit_rad_s_ = std::clamp(catch_up_factor_ * angle_rad(from, to) / gap_s, kMinCatchUpRate_rad_s, max_rate_rad_s_);
}

void TrackingDriver::on_pose(double capture_t_s, const geometry::Pose& X_WO, double now_s) {
  const bool first = !captured_ || lost_;
  if (!first) {
    // The frame interval, smoothed, bounded to sane camera rates (5 to 1000 Hz).
    const double interval = std::clamp(capture_t_s - last_capture_s_, 1e-3, 0.2);
    frame_interval_s_ = 0.8 * frame_interval_s_ + 0.2 * interval;
  }
  const double after = trajectory_.empty() ? -1e300 : trajectory_.poses().back().t_s;
  if (first) {
    // (Re)acquired: start from where the body is, or appear there if it never was.
    trajectory_.hold_from(now_s);
    const double t = std::max(now_s, after + 1e-9);
    if (trajectory_.empty()) {
      trajectory_.add(t, X_WO);
      lagging_ = false;
    } else {
      // Move there over one frame rather than teleport (longer if that is too fast).
      const geometry::Pose from = trajectory_.poses().back().X_WB;
      limit_catch_up(from, X_WO, captured_ ? capture_t_s - last_capture_s_ : 0.0);
      const double arrival = std::max(t + frame_interval_s_, earliest_arrival(t, from, X_WO));
      trajectory_.add(arrival, X_WO);
      lagging_ = arrival > capture_t_s + frame_interval_s_ + 1e-9;
    }
  } else if (policy_ == TrackingPolicy::kDelay) {
    // Behind (a catch-up, a flip turned at the limit): head for this pose from where the
    // body is, not via the one it has not reached yet.
    if (lagging_ && after > now_s) trajectory_.hold_from(now_s);
    const double last = trajectory_.poses().back().t_s;
    const double start = std::max(last, now_s);
    const geometry::Pose from = trajectory_.pose_at(start);
    const double nominal = capture_t_s + frame_interval_s_;
    const double arrival = std::max({nominal, last + 1e-9, earliest_arrival(start, from, X_WO)});
    trajectory_.add(arrival, X_WO);
    lagging_ = arrival > nominal + 1e-9;
    if (!lagging_) {  // caught up
      speed_limit_m_s_ = max_speed_m_s_;
      rate_limit_rad_s_ = max_rate_rad_s_;
    }
  } else {
    // Blend from the current (extrapolated) pose to the measurement over half a frame,
    // then keep going with the measured twist for one more frame.
    trajectory_.hold_from(now_s);
    const double blend_end = std::max(now_s + 0.5 * frame_interval_s_, after + 1e-9);
    const double lag = std::max(0.0, blend_end - capture_t_s);
    const geometry::ScrewMotion twist(last_pose_, X_WO);  // over (capture - last capture)
    const double span = std::max(capture_t_s - last_capture_s_, 1e-3);
    trajectory_.add(blend_end, twist.pose_at(1.0 + lag / span));
    trajectory_.add(blend_end + frame_interval_s_, twist.pose_at(1.0 + (lag + frame_interval_s_) / span));
  }
  trajectory_.forget_before(now_s - 1.0);
  last_capture_s_ = capture_t_s;
  captured_ = true;
  last_pose_ = X_WO;
  lost_ = false;
}

void TrackingDriver::shift_time(double by_s) {
  trajectory_.shift_time(by_s);
  last_capture_s_ += by_s;
}

void TrackingDriver::hold_at(double t_s, const geometry::Pose& X_WO) {
  trajectory_ = dynamics::KinematicTrajectory();
  trajectory_.add(t_s, X_WO);
  lost_ = true;
}

void TrackingDriver::on_lost(double now_s) {
  if (lost_) return;
  trajectory_.hold_from(now_s);
  lost_ = true;
}

}  // namespace arphys::sim
