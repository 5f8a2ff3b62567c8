#pragma once
// Bodies the World tests build scenes from: a static floor (the plane z = 0) and 1 kg cubes
// (as boxes or as meshes).
#include <memory>
#include <string>
#include <vector>

#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/world.hpp"
#include "simulator/geometry/mass_properties.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

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

// A cube as a 12-triangle mesh (mass properties of the solid cube).
inline RigidBody mesh_cube(const std::string& id, const Eigen::Vector3d& p, double side) {
  RigidBody b = cube(id, p, side);
  b.shape = collision::Shape::mesh(
      std::make_shared<const collision::CollisionMesh>(geometry::make_box_mesh(Eigen::Vector3d::Constant(side))));
  return b;
}

// The model and state a World keeps of these bodies (World::add_body splits each), for
// calling its stages directly.
struct StageWorld {
  WorldModel model;
  std::vector<BodyState> state;
};
inline StageWorld stage_world(const std::vector<RigidBody>& bodies, WorldOptions options = {}) {
  World world(std::move(options));
  for (const RigidBody& b : bodies) world.add_body(b);
  return {world.model(), world.state().bodies};
}

}  // namespace arphys::dynamics::testing
