#pragma once
// A rigid body of the simulation: its model (collision shape, mass properties, material and
// how it moves: static, kinematic: driven by tracking, dynamic: by the physics), fixed once
// a World holds it, and its state (pose, velocity, trajectory, sleep), which stepping
// changes. RigidBody is both together: what World::add_body takes and scene builders make.
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "simulator/collision/shape.hpp"
#include "simulator/dynamics/kinematic_trajectory.hpp"
#include "simulator/geometry/mass_properties.hpp"

namespace arphys::dynamics {

enum class BodyMotion { kStatic, kKinematic, kDynamic };

struct BodyModel {
  std::string id;
  std::string model;  // the scene object it comes from (spawned instances share it)
  bool real = false;  // a real object (tracked or fixed), as opposed to a virtual one
  BodyMotion motion = BodyMotion::kDynamic;
  collision::Shape shape = collision::Shape::plane();
  // Dynamic bodies: mass > 0; centre of mass and inertia about it in the body frame.
  geometry::MassProperties mass;
  double restitution = 0;          // in [0, 1]
  std::optional<double> friction;  // Coulomb coefficient; none: frictionless

  bool is_dynamic() const { return motion == BodyMotion::kDynamic; }
  // Radius about the body origin containing the whole shape (infinite for a plane).
  double bounding_radius_m() const;
};

// X_WB: body frame in the world; v_WBcm: velocity of the centre of mass; w_WB: angular
// velocity; all world frame, SI units.
struct BodyState {
  geometry::Pose X_WB = geometry::Pose::Identity();
  Eigen::Vector3d v_WBcm_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();
  KinematicTrajectory trajectory;  // kinematic bodies: where tracking says they are
  // A dynamic body at rest that a step holds fixed until something can reach it
  // (WorldOptions::sleep_after_s).
  bool asleep = false;
};

// Whether the physics moves the body now: dynamic and awake (a sleeper is held fixed).
inline bool moves(const BodyModel& m, const BodyState& s) { return m.is_dynamic() && !s.asleep; }
inline Eigen::Vector3d com_W(const BodyModel& m, const BodyState& s) { return s.X_WB * m.mass.center_of_mass_m; }
inline Eigen::Vector3d velocity_of_point(const BodyModel& m, const BodyState& s, const Eigen::Vector3d& p_W) {
  return s.v_WBcm_m_s + s.w_WB_rad_s.cross(p_W - com_W(m, s));
}
// Velocity of the body frame's origin (what scene files, world states and the CSV give).
inline Eigen::Vector3d origin_velocity(const BodyModel& m, const BodyState& s) {
  return velocity_of_point(m, s, s.X_WB.translation());
}
// The centre's velocity from the origin's v_WBo and the angular velocity w_WB.
inline Eigen::Vector3d com_velocity(const BodyModel& m, const BodyState& s, const Eigen::Vector3d& v_WBo_m_s,
                                    const Eigen::Vector3d& w_WB_rad_s) {
  return v_WBo_m_s + w_WB_rad_s.cross(com_W(m, s) - s.X_WB.translation());
}
Eigen::Matrix3d inertia_W(const BodyModel& m, const BodyState& s);
Eigen::Matrix3d inverse_inertia_W(const BodyModel& m, const BodyState& s);
double kinetic_energy_J(const BodyModel& m, const BodyState& s);  // 0 for a non-dynamic body

struct RigidBody : BodyModel, BodyState {
  Eigen::Vector3d com_W() const { return dynamics::com_W(*this, *this); }
  Eigen::Vector3d origin_velocity() const { return dynamics::origin_velocity(*this, *this); }
  Eigen::Matrix3d inertia_W() const { return dynamics::inertia_W(*this, *this); }
  double kinetic_energy_J() const { return dynamics::kinetic_energy_J(*this, *this); }
  // Sets the velocity from the origin's velocity and the angular velocity.
  void set_origin_velocity(const Eigen::Vector3d& v_WBo_m_s, const Eigen::Vector3d& w_rad_s) {
    v_WBcm_m_s = com_velocity(*this, *this, v_WBo_m_s, w_rad_s);
    w_WB_rad_s = w_rad_s;
  }
};

// X_WB moved so that the body's centre of mass (com_B, body frame) shifts by com_shift_W
// and the body turns by turn_rad about turn_axis_W (any length) through that centre; the
// rotation re-orthonormalised (thousands of such products drift off SO(3)). A step's
// integration and a position correction both move a body this way.
geometry::Pose moved_about_com(const geometry::Pose& X_WB, const Eigen::Vector3d& com_B,
                               const Eigen::Vector3d& com_shift_W, const Eigen::Vector3d& turn_axis_W, double turn_rad);

}  // namespace arphys::dynamics
