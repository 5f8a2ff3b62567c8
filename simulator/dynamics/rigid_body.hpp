#pragma once
// A rigid body of the simulation: its collision shape, its mass properties, how it
// moves (static, kinematic: driven by tracking, dynamic: by the physics) and its state.
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "simulator/collision/shape.hpp"
#include "simulator/dynamics/kinematic_trajectory.hpp"
#include "simulator/geometry/mass_properties.hpp"

namespace arphys::dynamics {

enum class BodyMotion { kStatic, kKinematic, kDynamic };

struct RigidBody {
  std::string id;
  std::string model;  // the scene object it comes from (spawned instances share it)
  bool real = false;  // a real object (tracked or fixed), as opposed to a virtual one
  BodyMotion motion = BodyMotion::kDynamic;
  collision::Shape shape = collision::Shape::plane();
  // Dynamic bodies: mass > 0; centre of mass and inertia about it in the body frame.
  geometry::MassProperties mass;
  double restitution = 0;           // in [0, 1]
  std::optional<double> friction;   // Coulomb coefficient; none: frictionless
  KinematicTrajectory trajectory;   // kinematic bodies: where tracking says they are

  // State. X_WB: body frame in the world; v_WC: velocity of the centre of mass;
  // w_W: angular velocity; all world frame, SI units.
  geometry::Pose X_WB = geometry::Pose::Identity();
  Eigen::Vector3d v_WBcm_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();

  bool is_dynamic() const { return motion == BodyMotion::kDynamic; }
  Eigen::Vector3d com_W() const { return X_WB * mass.center_of_mass_m; }
  Eigen::Vector3d velocity_of_point(const Eigen::Vector3d& p_W) const { return v_WBcm_m_s + w_WB_rad_s.cross(p_W - com_W()); }
  // Velocity of the body frame's origin (what the CSV reports).
  Eigen::Vector3d origin_velocity() const { return velocity_of_point(X_WB.translation()); }
  // Sets the state from the origin's velocity and the angular velocity (scene files,
  // spawn commands and world states give the origin's; the state keeps the centre's).
  void set_origin_velocity(const Eigen::Vector3d& v_WO_m_s, const Eigen::Vector3d& w_rad_s) {
    w_WB_rad_s = w_rad_s;
    v_WBcm_m_s = v_WO_m_s + w_rad_s.cross(com_W() - X_WB.translation());
  }
  Eigen::Matrix3d inertia_W() const {
    const Eigen::Matrix3d R = X_WB.linear();
    return R * mass.inertia_about_com_kg_m2 * R.transpose();
  }
  Eigen::Matrix3d inverse_inertia_W() const;
  double kinetic_energy_J() const;
  // Radius about the body origin containing the whole shape (infinite for a plane).
  double bounding_radius_m() const;
};

// X_WB moved so that the body's centre of mass (com_B, body frame) shifts by com_shift_W
// and the body turns by turn_rad about turn_axis_W (any length) through that centre; the
// rotation re-orthonormalised (thousands of such products drift off SO(3)). A step's
// integration and a position correction both move a body this way.
geometry::Pose moved_about_com(const geometry::Pose& X_WB, const Eigen::Vector3d& com_B,
                               const Eigen::Vector3d& com_shift_W, const Eigen::Vector3d& turn_axis_W, double turn_rad);

}  // namespace arphys::dynamics
