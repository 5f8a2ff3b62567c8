#include "simulator/dynamics/kinematic_trajectory.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "simulator/geometry/screw_motion.hpp"

namespace arphys::dynamics {

void KinematicTrajectory::add(double t_s, const geometry::Pose& X_WB) {
  if (!std::isfinite(t_s)) throw std::invalid_argument("KinematicTrajectory::add: time is not finite");
  if (!X_WB.matrix().allFinite())
    throw std::invalid_argument("KinematicTrajectory::add: pose at t = " + std::to_string(t_s) + " s is not finite");
  if (!poses_.empty() && !(t_s > poses_.back().t_s))
    throw std::invalid_argument("KinematicTrajectory::add: time " + std::to_string(t_s) +
                                " s does not follow the last one, " + std::to_string(poses_.back().t_s) + " s");
  poses_.push_back({t_s, X_WB});
}

void KinematicTrajectory::forget_before(double t_s) {
  const int i = segment(t_s);
  if (i > 0) poses_.erase(poses_.begin(), poses_.begin() + i);
}

int KinematicTrajectory::segment(double t_s) const {
  if (poses_.size() < 2 || t_s < poses_.front().t_s || t_s >= poses_.back().t_s) return -1;
  const auto it = std::upper_bound(poses_.begin(), poses_.end(), t_s,
                                   [](double t, const TimedPose& p) { return t < p.t_s; });
  return static_cast<int>(it - poses_.begin()) - 1;
}

void KinematicTrajectory::shift_time(double by_s) {
  for (TimedPose& pose : poses_) pose.t_s += by_s;
}

void KinematicTrajectory::hold_from(double t_s) {
  if (poses_.empty()) return;
  const geometry::Pose X = pose_at(t_s);
  while (!poses_.empty() && poses_.back().t_s > t_s) poses_.pop_back();
  if (poses_.empty() || poses_.back().t_s < t_s) poses_.push_back({t_s, X});
}

geometry::Pose KinematicTrajectory::pose_at(double t_s) const {
  if (poses_.empty()) return geometry::Pose::Identity();
  const int i = segment(t_s);
  if (i < 0) return t_s < poses_.front().t_s ? poses_.front().X_WB : poses_.back().X_WB;
  const TimedPose& a = poses_[i];
  const TimedPose& b = poses_[i + 1];
  return geometry::ScrewMotion(a.X_WB, b.X_WB).pose_at((t_s - a.t_s) / (b.t_s - a.t_s));
}

Twist KinematicTrajectory::twist_at(double t_s) const {
  const int i = segment(t_s);
  if (i < 0) return {};
  const TimedPose& a = poses_[i];
  const TimedPose& b = poses_[i + 1];
  const double duration = b.t_s - a.t_s;
  const geometry::ScrewMotion screw(a.X_WB, b.X_WB);
  const geometry::Pose X = pose_at(t_s);
  Twist twist;
  twist.w_WB_rad_s = screw.angular_velocity() / duration;
  twist.v_WBo_m_s = screw.velocity_of_point(X.translation()) / duration;
  return twist;
}

}  // namespace arphys::dynamics
