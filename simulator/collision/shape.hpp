#pragma once
// Collision shapes: "model no more than a scene needs". A table is a plane or a box,
// a ball a sphere; only what needs its real form is a mesh. A box is queried as its
// 12-triangle mesh (built once here), which the mesh code handles exactly.
#include <memory>
#include <string>

#include <Eigen/Core>

#include "simulator/collision/collision_mesh.hpp"

namespace arphys::collision {

class Shape {
 public:
  enum class Type { kPlane, kBox, kSphere, kMesh };

  // The half-space z <= 0 of the body frame; its boundary is the plane z = 0.
  static Shape plane();
  // A box centred on the body origin, full side lengths in metres (each > 0).
  static Shape box(const Eigen::Vector3d& size_m);
  // A sphere centred on the body origin (radius > 0).
  static Shape sphere(double radius_m);
  static Shape mesh(std::shared_ptr<const CollisionMesh> mesh);

  Type type() const { return type_; }
  double radius_m() const { return radius_m_; }
  const Eigen::Vector3d& size_m() const { return size_m_; }
  // The triangle mesh of a box or a mesh shape; null for planes and spheres.
  const CollisionMesh* triangles() const { return mesh_.get(); }
  std::string describe() const;

 private:
  Type type_ = Type::kPlane;
  double radius_m_ = 0;
  Eigen::Vector3d size_m_ = Eigen::Vector3d::Zero();
  std::shared_ptr<const CollisionMesh> mesh_;
};

}  // namespace arphys::collision
