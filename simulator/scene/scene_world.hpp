#pragma once
// Builds a World from a scene file: shapes (each mesh loaded once), mass properties
// (exact for meshes, analytic for primitives), motions, initial states, scripted
// trajectories and spawned instances. Kept out of the engine: the dynamics library does
// not know the scene file's schema.
#include <memory>
#include <string>

#include "configs/loader/scene_config.hpp"
#include "simulator/dynamics/world.hpp"

namespace arphys::scene {

using dynamics::RigidBody;
using dynamics::World;
using dynamics::WorldOptions;

// Mass properties of an object's collision shape: exact volume integration for a
// mesh (its holes capped), analytic for a box or sphere; mass_kg if given, else
// density_kg_m3 (default that of water). Throws std::invalid_argument naming the
// object for a plane or an open mesh that cannot be closed.
geometry::MassProperties mass_properties_of(const config::ObjectConfig& object);

// The collision shape of an object (meshes loaded with their scale).
collision::Shape shape_of(const config::ShapeConfig& shape);

// World options from the scene's physics section.
WorldOptions world_options_of(const config::SceneConfig& scene);

// The bodies of the scene: one per static or kinematic object (id = object id), and
// per dynamic object one body, or one per spawn.at_start entry (ids "id#0", "id#1", ...).
// threads: WorldOptions::threads (a property of the run, not of the scene).
World build_world(const config::SceneConfig& scene, int threads = 1);

// A body for one instance of a dynamic object at a pose and velocity (origin velocity).
RigidBody make_instance(const config::ObjectConfig& object, const std::string& id, const geometry::Pose& X_WB,
                        const Eigen::Vector3d& v_WO_m_s, const Eigen::Vector3d& w_WB_rad_s);

}  // namespace arphys::scene
