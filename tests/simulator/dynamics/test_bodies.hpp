#pragma once
// Bodies the World tests build scenes from: a static floor (the plane z = 0) and 1 kg cubes.
#include <string>

#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/geometry/mass_properties.hpp"

namespace arphys::dynamics::testing {

inline RigidBody plane_body() {
  RigidBody b;
  b.id = "floor";
  b.motion = BodyMotion::kStatic;
  b.shape = collision::Shape::plane();
  return b;
}

inline RigidBody cube(const std::string& id, const Eigen::Vector3d& p, double side = 0.2) {
  RigidBody b;
  b.id = id;
  b.shape = collision::Shape::box(Eigen::Vector3d::Constant(side));
  b.mass = geometry::with_mass(geometry::box_mass_properties(Eigen::Vector3d::Constant(side), 1000), 1.0);
  b.X_WB = geometry::translation_pose(p);
  return b;
}

}  // namespace arphys::dynamics::testing
