#include "simulator/collision/screw_enclosure.hpp"

namespace arphys::collision {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& u) {
  Eigen::Matrix3d K;
  K << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  return K;
}

// libm sin (< 1 ulp) plus one division or multiplication: 4 ulps is a safe bound.
constexpr double kUlps = 4.0;

}  // namespace

ScrewEnclosure::ScrewEnclosure(const geometry::ScrewMotion& motion, const geometry::Pose& X_WF) {
  const Eigen::Matrix3d R_FW = X_WF.linear().transpose();
  angle_ = motion.angle_rad();
  axial_ = motion.axial_displacement_m();
  axis_ = R_FW * motion.axis();
  // World: velocity_of_point(p) = w u x p - k + s u, so k = s u - v(0).
  const Eigen::Vector3d k_W = axial_ * motion.axis() - motion.velocity_of_point(Eigen::Vector3d::Zero());
  // In F: v_F(y) = R_FW v_W(X_WF y)  =>  k_F = R_FW (k_W - w u_W x p_WF).
  k_ = R_FW * (k_W - angle_ * motion.axis().cross(X_WF.translation()));
}

Eigen::Vector3d ScrewEnclosure::point_at(const Eigen::Vector3d& y, double t) const {
  if (angle_ == 0) return y - t * k_ + (t * axial_) * axis_;
  const double S = std::sin(angle_ * t) / angle_;
  const double h = std::sin(0.5 * angle_ * t);
  const double C = 2 * h * h / angle_;
  const Eigen::Vector3d v = angle_ * axis_.cross(y) - k_;
  return y + S * v + C * axis_.cross(v) + (t * axial_) * axis_;
}

Interval ScrewEnclosure::S_over(const Interval& T) const {
  if (angle_ == 0) return T;
  auto S = [&](double t) { return Interval::around(std::sin(angle_ * t) / angle_, kUlps); };
  Interval out = hull(S(T.lo), S(T.hi));
  // The maximum 1/w at w t = pi/2 (only when pi/2 lies inside w T).
  if (angle_ * T.lo <= M_PI_2 + 1e-12 && angle_ * T.hi >= M_PI_2 - 1e-12) out.hi = interval_detail::up(1.0 / angle_);
  return out;
}

Interval ScrewEnclosure::C_over(const Interval& T) const {
  if (angle_ == 0) return Interval(0.0);
  auto C = [&](double t) {
    const double h = std::sin(0.5 * angle_ * t);
    return Interval::around(2 * h * h / angle_, kUlps + 2);
  };
  return hull(C(T.lo), C(T.hi));  // increasing on [0, pi / w]
}

IVec3 ScrewEnclosure::point_over(const Eigen::Vector3d& y, const Interval& T) const {
  const Eigen::Vector3d along = axial_ * axis_;
  if (angle_ == 0) return (T * (along - k_)) + y;
  const Eigen::Vector3d v = angle_ * axis_.cross(y) - k_;
  return S_over(T) * v + C_over(T) * axis_.cross(v) + T * along + y;
}

Eigen::Matrix3d ScrewEnclosure::rotation_at(double t) const {
  if (angle_ == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle_ * t, axis_).toRotationMatrix();
}

IMat3 ScrewEnclosure::rotation_over(const Interval& T) const {
  if (angle_ == 0) return IMat3::point(Eigen::Matrix3d::Identity());
  // R = I + sin(wt) K + (1 - cos(wt)) K^2, with sin(wt) = w S and 1 - cos(wt) = w C.
  const Interval sin_wt = angle_ * S_over(T);
  const Interval one_minus_cos = angle_ * C_over(T);
  const Eigen::Matrix3d K = skew(axis_), K2 = K * K;
  IMat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.m[i][j] = K(i, j) * sin_wt + K2(i, j) * one_minus_cos + (i == j ? 1.0 : 0.0);
  return R;
}

Eigen::Vector3d ScrewEnclosure::inverse_point_at(const Eigen::Vector3d& z, double t) const {
  const Eigen::Vector3d origin = point_at(Eigen::Vector3d::Zero(), t);
  return rotation_at(t).transpose() * (z - origin);
}

IVec3 ScrewEnclosure::inverse_point_over(const IVec3& z, const Interval& T) const {
  const IVec3 origin = point_over(Eigen::Vector3d::Zero(), T);
  if (angle_ == 0) return z - origin;
  return rotation_over(T).transpose() * (z - origin);
}

RelativeMotion::RelativeMotion(const geometry::ScrewMotion& motion_A, const geometry::ScrewMotion& motion_B)
    : X_FB_(motion_A.start().inverse() * motion_B.start()),
      a_(motion_A, motion_A.start()),
      b_(motion_B, motion_A.start()) {
  omega_B_ = b_.omega();
  c_B_ = b_.linear_velocity();
  delta_omega_ = b_.omega() - a_.omega();
  delta_c_ = b_.linear_velocity() - a_.linear_velocity();
  delta_omega_norm_ = interval_detail::up(delta_omega_.norm() * (1 + 1e-12));
  omega_A_norm_ = a_.angle_rad();
}

Eigen::Vector3d RelativeMotion::point_at(const Eigen::Vector3d& p_B, double t) const {
  const Eigen::Vector3d z = b_.point_at(X_FB_ * p_B, t);
  return a_.is_identity() ? z : a_.inverse_point_at(z, t);
}

IVec3 RelativeMotion::point_over(const Eigen::Vector3d& p_B, const Interval& T) const {
  const IVec3 z = b_.point_over(X_FB_ * p_B, T);
  return a_.is_identity() ? z : a_.inverse_point_over(z, T);
}

Eigen::Matrix3d RelativeMotion::rotation_at(double t) const {
  return a_.rotation_at(t).transpose() * b_.rotation_at(t) * X_FB_.linear();
}

namespace {
// Half-width of T around its midpoint, rounded up.
double half_width(const Interval& T, double mid) { return interval_detail::up(std::max(T.hi - mid, mid - T.lo)); }
constexpr double kRoundingSlack = 1e-12;
}  // namespace

Interval MovingPoint::project(const Eigen::Vector3d& L, double offset) const {
  const double value = L.dot(mid) - offset;
  const double norm_L = L.norm();
  const double radius = half_width * (std::abs(L.dot(velocity)) + norm_L * velocity_rad) + norm_L * rounding;
  // The dot products are rounded within 3 ulps of the sum of their terms' magnitudes.
  const double slack = 1e-15 * (L.cwiseAbs().dot(mid.cwiseAbs()) + std::abs(offset) +
                                half_width * L.cwiseAbs().dot(velocity.cwiseAbs()));
  const double r = interval_detail::up(radius * (1 + 1e-12) + slack);
  return {interval_detail::down(value - r), interval_detail::up(value + r)};
}

MidRadVector MovingPoint::ball() const {
  MidRadVector out;
  out.mid = mid;
  for (int i = 0; i < 3; ++i)
    out.rad[i] = interval_detail::up((half_width * (std::abs(velocity[i]) + velocity_rad) + rounding) * (1 + 1e-12));
  return out;
}

RelativeMotion::Snapshot RelativeMotion::snapshot(const Interval& T) const {
  Snapshot s;
  s.T = T;
  s.tm = T.mid();
  s.h = half_width(T, s.tm);
  geometry::Pose D_b = geometry::Pose::Identity();
  D_b.linear() = b_.rotation_at(s.tm);
  D_b.translation() = b_.point_at(Eigen::Vector3d::Zero(), s.tm);
  s.X_FB = D_b * X_FB_;
  if (a_.is_identity()) {
    s.R_AF.setIdentity();
    s.X_AB = s.X_FB;
  } else {
    geometry::Pose D_a = geometry::Pose::Identity();
    D_a.linear() = a_.rotation_at(s.tm);
    D_a.translation() = a_.point_at(Eigen::Vector3d::Zero(), s.tm);
    s.R_AF = D_a.linear().transpose();
    s.X_AB = D_a.inverse(Eigen::Isometry) * s.X_FB;
  }
  s.R_AB.mid = s.X_AB.linear();
  s.translation_scale = s.X_AB.translation().cwiseAbs().sum() + X_FB_.translation().cwiseAbs().sum() +
                        s.X_FB.translation().cwiseAbs().sum();
  // Each column turns by at most (w_A + w_B) |t - tm|.
  s.R_AB.rad.setConstant(
      interval_detail::up(s.h * (a_.angle_rad() + b_.angle_rad()) * (1 + kRoundingSlack) + kRoundingSlack));
  return s;
}

MovingPoint RelativeMotion::moving_point(const Eigen::Vector3d& p_B, const Snapshot& s) const {
  // In frame F, B's point is at x(t) with speed |v_B(x)| (constant along its path), and
  // p(t) = R_A(t)^T (x(t) - o_A(t)) in A's frame, so
  //   p'  = R_A^T g(x),  g(x) = v_B(x) - v_A(x) = (w_B - w_A) x x + (c_B - c_A),
  //   p'' = R_A^T (-w_A x g(x) + (w_B - w_A) x x'),
  // which bounds |p'(t) - p'(tm)| by h (|w_A| max|g| + |w_B - w_A| speed_B).
  MovingPoint out;
  out.half_width = s.h;
  const double h = s.h;
  const Eigen::Vector3d x = s.X_FB * p_B;
  const Eigen::Vector3d g = delta_omega_.cross(x) + delta_c_;
  out.mid = s.X_AB * p_B;
  if (a_.is_identity()) {
    out.velocity = g;  // = v_B(x)
    out.velocity_rad = h * delta_omega_norm_ * g.norm();
  } else {
    const double speed_B = (omega_B_.cross(x) + c_B_).norm();
    const double g_norm = g.norm();
    out.velocity = s.R_AF * g;
    out.velocity_rad = h * (omega_A_norm_ * (g_norm + delta_omega_norm_ * speed_B * h) + delta_omega_norm_ * speed_B);
  }
  out.velocity_rad = out.velocity_rad * (1 + kRoundingSlack) + kRoundingSlack * out.velocity.cwiseAbs().sum();
  out.rounding = kRoundingSlack * (p_B.cwiseAbs().sum() + x.cwiseAbs().sum() + out.mid.cwiseAbs().sum() + s.translation_scale);
  return out;
}


}  // namespace arphys::collision
