#pragma once
#include <Eigen/Geometry>

#include "simulator/geometry/pose.hpp"

namespace arphys::geometry {

// The screw motion between two poses of a body (docs/method.md section 1):
//   X(t) = exp(t log(X1 X0^-1)) X0,   t in [0, 1],
// a rotation at constant rate about a fixed world axis plus a constant translation
// along that axis. The rotation angle is taken in [0, pi]; at exactly pi the axis
// sign is the one Eigen's quaternion gives (both are valid screws).
//
// The displacement D(t) = X(t) X0^-1 is evaluated as
//   R(t) = Rot(u, t*theta),  p(t) = a(t) q + b(t) (u x q) + t s u
// with q the part of D's translation normal to the axis, s = u.p the axial part,
//   a(t) = sin(t h) cos(t h - h) / sin h,  b(t) = sin(t h) sin(t h - h) / sin h,  h = theta/2.
// Both stay bounded as theta -> 0 (a -> t, b -> 0), so pure translation needs no
// special case and there is no cot(theta/2) blow-up near zero rotation.
class ScrewMotion {
 public:
  // X0, X1: world-from-body poses at t = 0 and t = 1.
  ScrewMotion(const Pose& X0, const Pose& X1);

  // Pose at t; exactly X0 at t = 0 and X1 at t = 1. t outside [0, 1] extrapolates.
  Pose pose_at(double t) const;
  // D(t) = X(t) X0^-1: the world-frame displacement applied to any point of the body.
  Pose displacement_at(double t) const;

  const Pose& start() const { return X0_; }
  const Pose& end() const { return X1_; }
  // Unit screw axis direction in the world (z when there is no rotation).
  const Eigen::Vector3d& axis() const { return axis_; }
  // Total rotation angle over t in [0, 1], radians, in [0, pi].
  double angle_rad() const { return angle_rad_; }
  // Total translation along the axis over t in [0, 1], metres.
  double axial_displacement_m() const { return axial_m_; }
  // Total translation normal to the axis of the displacement's origin image, metres.
  const Eigen::Vector3d& normal_translation_m() const { return normal_translation_m_; }
  bool is_pure_translation() const { return angle_rad_ == 0.0; }

  // Angular velocity (world frame), radians per unit of t: constant along the motion.
  Eigen::Vector3d angular_velocity() const { return angle_rad_ * axis_; }
  // Velocity (world frame, metres per unit of t) of the body point that is at p_W now.
  // Exact for any t since the screw's velocity field is constant in the world.
  Eigen::Vector3d velocity_of_point(const Eigen::Vector3d& p_W) const;

 private:
  Pose X0_, X1_;
  Eigen::Vector3d axis_{0, 0, 1};
  double angle_rad_ = 0;
  double axial_m_ = 0;
  Eigen::Vector3d normal_translation_m_{0, 0, 0};
};

// How far apart, at most, a body point's places on two screw motions from the same start
// pose get over t in [0, 1], for any point within radius_m of the body's origin at the
// start. The two paths part no faster than the velocity field of the motions' difference
// (the first motion's field only turns the gap between them); bounded at the origin and
// along its path on `before` (as long as its constant speed there), that is
//   |v_now(o) - v_before(o)| + |w_now - w_before| (radius_m + |v_before(o)|).
double motion_change_bound_m(const ScrewMotion& before, const ScrewMotion& now, double radius_m);

}  // namespace arphys::geometry
