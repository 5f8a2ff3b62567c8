#pragma once
// Interval enclosures of points moving under a screw motion, for the continuous tests.
//
// A screw displacement maps a point y (fixed frame F) at time t to
//   D(t) y = y + S(t) v(y) + C(t) u x v(y) + t s u,    v(y) = w u x y - k,
// with S(t) = sin(w t) / w and C(t) = (1 - cos(w t)) / w = 2 sin^2(w t / 2) / w.
// v(y) is the point's velocity normal to the axis (constant in F), so every term is
// bounded as w -> 0 (S -> t, C -> 0): no axis point at infinity, no special case
// for pure translation. With w in [0, pi] and t in [0, 1], C is increasing and S has
// at most one maximum (at w t = pi / 2), so the enclosures of S and C over a time
// interval are their end values (plus that maximum): tight, not just valid.
#include <Eigen/Geometry>

#include "simulator/collision/interval.hpp"
#include "simulator/geometry/screw_motion.hpp"

namespace arphys::collision {

// A point's path over a time interval T = [tm - h, tm + h] to first order: p(t) lies
// within (t - tm) (velocity +- velocity_rad) of mid. Linear functionals of it are
// then enclosed to second order, which keeps a point sliding parallel to a face (zero
// normal velocity) from looking like a root at every scale.
struct MovingPoint {
  Eigen::Vector3d mid;           // p(tm), metres
  Eigen::Vector3d velocity;      // p'(tm), metres per unit t
  double velocity_rad = 0;       // bound on |p'(t) - p'(tm)| over T
  double half_width = 0;         // h
  double rounding = 0;           // bound on the rounding error of mid

  // Enclosure of L . p(t) - offset over T.
  Interval project(const Eigen::Vector3d& L, double offset) const;
  // Componentwise enclosure of p(t) over T.
  MidRadVector ball() const;
};

class ScrewEnclosure {
 public:
  // The screw of `motion` (world frame) expressed in frame F, given X_WF.
  ScrewEnclosure(const geometry::ScrewMotion& motion, const geometry::Pose& X_WF);
  ScrewEnclosure() = default;  // identity motion

  bool is_identity() const { return angle_ == 0 && axial_ == 0 && k_.isZero(0); }
  bool rotates() const { return angle_ != 0; }

  double angle_rad() const { return angle_; }
  // The screw's velocity field v(x) = omega x x + linear, constant in frame F.
  Eigen::Vector3d omega() const { return angle_ * axis_; }
  Eigen::Vector3d linear_velocity() const { return axial_ * axis_ - k_; }

  // D(t) y, exactly in double precision.
  Eigen::Vector3d point_at(const Eigen::Vector3d& y, double t) const;
  // Enclosure of { D(t) y : t in T }, T a subset of [0, 1].
  IVec3 point_over(const Eigen::Vector3d& y, const Interval& T) const;
  // The rotation part of D(t), and its enclosure over T.
  Eigen::Matrix3d rotation_at(double t) const;
  IMat3 rotation_over(const Interval& T) const;
  // Enclosure of D(t)^-1 z over T for z known to lie in the box `z` at each such t.
  IVec3 inverse_point_over(const IVec3& z, const Interval& T) const;
  Eigen::Vector3d inverse_point_at(const Eigen::Vector3d& z, double t) const;

 private:
  // sin(w t) / w and (1 - cos(w t)) / w enclosed over T.
  Interval S_over(const Interval& T) const;
  Interval C_over(const Interval& T) const;

  Eigen::Vector3d axis_{0, 0, 1};  // u, in F
  double angle_ = 0;               // w, radians over t in [0, 1]
  double axial_ = 0;               // s, metres over t in [0, 1]
  Eigen::Vector3d k_{0, 0, 0};     // w u x c (c: a point of the axis), in F
};

// The motion of body B seen from body A: for points of B (in B's body frame) their
// positions in A's body frame over time, both bodies moving on their own screws.
// Exact when A does not rotate; when both rotate the enclosures compose A's inverse
// rotation enclosure and stay valid, only looser.
class RelativeMotion {
 public:
  RelativeMotion(const geometry::ScrewMotion& motion_A, const geometry::ScrewMotion& motion_B);

  // Centered (mean-value) enclosures over T, what the CCD uses: the value at T's
  // midpoint, the velocity there and a bound on its change (MovingPoint), first-order
  // tight and much cheaper than the natural interval extension below. A Snapshot holds
  // what every point of B shares over T, computed once (the trigonometry): the relative
  // pose at T's midpoint and the rotation enclosure.
  struct Snapshot {
    Interval T;
    double tm = 0, h = 0;
    geometry::Pose X_AB;   // B body -> A body at tm
    geometry::Pose X_FB;   // B body -> frame F at tm (B's point in F, where the velocity fields live)
    Eigen::Matrix3d R_AF;  // F -> A body at tm
    MidRadMatrix R_AB;     // rotation B -> A over T
    double translation_scale = 0;  // magnitude of the poses' translations, for rounding bounds
  };
  Snapshot snapshot(const Interval& T) const;
  MovingPoint moving_point(const Eigen::Vector3d& p_B, const Snapshot& snapshot) const;
  MovingPoint moving_point(const Eigen::Vector3d& p_B, const Interval& T) const {
    return moving_point(p_B, snapshot(T));
  }
  MidRadVector point_ball(const Eigen::Vector3d& p_B, const Interval& T) const { return moving_point(p_B, T).ball(); }
  MidRadMatrix rotation_ball(const Interval& T) const { return snapshot(T).R_AB; }

  // X_AB(t) applied to p_B, and its natural interval extension over T (the tests'
  // independent second enclosure of the same motion).
  Eigen::Vector3d point_at(const Eigen::Vector3d& p_B, double t) const;
  IVec3 point_over(const Eigen::Vector3d& p_B, const Interval& T) const;
  // R_AB(t).
  Eigen::Matrix3d rotation_at(double t) const;
  // Bound on the angular speed of B relative to A (radians per unit t): |w_B - w_A|.
  double angular_speed() const { return interval_detail::up((b_.omega() - a_.omega()).norm() * (1 + 1e-12)); }

 private:
  geometry::Pose X_FB_;  // X_A0^-1 X_B0
  ScrewEnclosure a_, b_;  // A's and B's screws in F
  // Velocity fields in F, cached for moving_point: v_B(x) = omega_B x x + c_B, and the
  // relative field g(x) = v_B(x) - v_A(x) = delta_omega x x + delta_c.
  Eigen::Vector3d omega_B_, c_B_, delta_omega_, delta_c_;
  double delta_omega_norm_ = 0, omega_A_norm_ = 0;
};

}  // namespace arphys::collision
