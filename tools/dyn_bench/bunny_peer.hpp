#pragma once
// A peer engine stepping the paper's bunny scenes (tools/dyn_bench/bunnies_peers.hpp): the
// bodies as arphys builds them from the scene (the table and the tracked box are boxes, a
// bunny is its convex pieces, or the mesh they were made from for the peers that collide
// meshes), the bunny's mass and inertia as arphys computes them, and poses reported in
// arphys's body frames so that one overlap measure serves every engine.
#include <memory>
#include <vector>

#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::dyn_bench {

struct BunnyModel {
  std::vector<dynamics::RigidBody> bodies;
  Eigen::Vector3d gravity_m_s2 = Eigen::Vector3d(0, 0, -9.81);
  geometry::TriangleMesh bunny_mesh;  // the pieces' source mesh, scaled, in the bunny's body frame
};

class BunnyPeer {
 public:
  virtual ~BunnyPeer() = default;
  // A kinematic body's pose at the end of the coming step, and its velocity over it.
  virtual void set_kinematic(int i, const geometry::Pose& X_WB, const Eigen::Vector3d& v_W_m_s) = 0;
  virtual void step(double dt_s) = 0;
  virtual geometry::Pose pose(int i) const = 0;  // X_WB, arphys's body frame
  // The engine gave up on its state (MuJoCo resets a simulation whose accelerations blow
  // up): the run stops there and reports the time it reached.
  virtual bool diverged() const { return false; }
};

// Bullet 3.24: a compound of the pieces' hulls per bunny, or GImpact on its mesh.
std::unique_ptr<BunnyPeer> make_bullet_bunnies(const BunnyModel& model, bool gimpact);
// MuJoCo 2.2.2: each piece a mesh geom (MuJoCo collides a mesh as its convex hull).
std::unique_ptr<BunnyPeer> make_mujoco_bunnies(const BunnyModel& model, double dt_s);
// ODE 0.16 quickstep: the bunny's mesh as a trimesh.
std::unique_ptr<BunnyPeer> make_ode_bunnies(const BunnyModel& model);

// The principal frame P of a dynamic body (origin at its centre of mass, axes its principal
// axes, right-handed) in its body frame, and its principal moments.
geometry::Pose principal_frame(const dynamics::RigidBody& body, Eigen::Vector3d* moments_kg_m2);

}  // namespace arphys::dyn_bench
