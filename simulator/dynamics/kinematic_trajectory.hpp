#pragma once
// The motion of a kinematic body (a tracked real object): timed poses, and between two
// of them the screw motion (continuous, no teleport) with its constant twist, so the
// body pushes what it meets smoothly. Before the first pose it holds the first, after
// the last it holds the last, at rest.
#include <vector>

#include "simulator/geometry/pose.hpp"

namespace arphys::dynamics {

struct TimedPose {
  double t_s = 0;
  geometry::Pose X_WB = geometry::Pose::Identity();
};

// Velocity of a rigid body: of its frame origin and its angular velocity, world frame.
struct Twist {
  Eigen::Vector3d v_WBo_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();
  // Velocity of the body point at p_W, when the origin is at p_WBo.
  Eigen::Vector3d velocity_of_point(const Eigen::Vector3d& p_W, const Eigen::Vector3d& p_WBo) const {
    return v_WBo_m_s + w_WB_rad_s.cross(p_W - p_WBo);
  }
};

class KinematicTrajectory {
 public:
  // Appends a pose; times must increase strictly (throws std::invalid_argument naming
  // the time otherwise, or when the pose is not finite).
  void add(double t_s, const geometry::Pose& X_WB);
  bool empty() const { return poses_.empty(); }
  std::size_t size() const { return poses_.size(); }
  const std::vector<TimedPose>& poses() const { return poses_; }
  // Drops poses older than t_s except the one in effect at t_s (for long live runs).
  void forget_before(double t_s);
  // Replaces everything after t_s by the pose the body has at t_s: it stops there.
  void hold_from(double t_s);
  // Moves every pose by by_s in time (the clock the poses are timed in moved).
  void shift_time(double by_s);

  geometry::Pose pose_at(double t_s) const;
  // The twist in effect at t_s (of the segment containing it; zero outside).
  Twist twist_at(double t_s) const;

 private:
  // Index i with poses_[i].t_s <= t < poses_[i + 1].t_s, or -1 outside.
  int segment(double t_s) const;
  std::vector<TimedPose> poses_;
};

}  // namespace arphys::dynamics
