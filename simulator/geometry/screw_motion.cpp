#include "simulator/geometry/screw_motion.hpp"

#include <cmath>

namespace arphys::geometry {
namespace {

// sin(x)/x, accurate near 0.
double sinc(double x) {
  if (std::abs(x) < 1e-4) return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}

}  // namespace

ScrewMotion::ScrewMotion(const Pose& X0, const Pose& X1) : X0_(X0), X1_(X1) {
  const Eigen::Matrix3d R = X1.linear() * X0.linear().transpose();
  const Eigen::Vector3d p = X1.translation() - R * X0.translation();
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // angle in [0, pi]
  const double vnorm = q.vec().norm();
  if (vnorm > 0) {
    angle_rad_ = 2.0 * std::atan2(vnorm, q.w());
    axis_ = q.vec() / vnorm;
  }
  axial_m_ = axis_.dot(p);
  normal_translation_m_ = p - axial_m_ * axis_;
}

Pose ScrewMotion::displacement_at(double t) const {
  if (t == 0.0) return Pose::Identity();
  if (t == 1.0) return X1_ * X0_.inverse();
  const double h = 0.5 * angle_rad_;
  // r = sin(t h) / sin(h), written with sinc so that it tends to t as h -> 0.
  const double r = (h == 0.0) ? t : t * sinc(t * h) / sinc(h);
  const double a = r * std::cos(t * h - h);
  const double b = r * std::sin(t * h - h);
  Pose D = Pose::Identity();
  D.linear() = Eigen::AngleAxisd(t * angle_rad_, axis_).toRotationMatrix();
  D.translation() = a * normal_translation_m_ + b * axis_.cross(normal_translation_m_) + t * axial_m_ * axis_;
  return D;
}

Pose ScrewMotion::pose_at(double t) const {
  if (t == 0.0) return X0_;
  if (t == 1.0) return X1_;
  return displacement_at(t) * X0_;
}

Eigen::Vector3d ScrewMotion::velocity_of_point(const Eigen::Vector3d& p_W) const {
  // v = w x (p - c) + s u, with c the point of the axis closest to the origin:
  //   c = (q + cot(h) u x q) / 2, so w x c = (theta/2) u x q - (cos h / sinc h) q.
  const double h = 0.5 * angle_rad_;
  const Eigen::Vector3d w = angular_velocity();
  const Eigen::Vector3d w_cross_c =
      h * axis_.cross(normal_translation_m_) - (std::cos(h) / sinc(h)) * normal_translation_m_;
  return w.cross(p_W) - w_cross_c + axial_m_ * axis_;
}

double motion_change_bound_m(const ScrewMotion& before, const ScrewMotion& now, double radius_m) {
  const Eigen::Vector3d o_W = before.start().translation();
  const Eigen::Vector3d v_before = before.velocity_of_point(o_W);
  const double dw = (now.angular_velocity() - before.angular_velocity()).norm();
  return (now.velocity_of_point(o_W) - v_before).norm() + dw * (radius_m + v_before.norm());
}

}  // namespace arphys::geometry
