#pragma once
// Collision shapes: "model no more than a scene needs". A table is a plane or a box,
// a ball a sphere; a dynamic concave body a few convex pieces; only what needs its real
// surface is a mesh. A box is swept as its 12-triangle mesh (built once here), which the
// mesh code handles exactly, and meets convex pieces as a one-piece convex set.
#include <memory>
#include <string>

#include <Eigen/Core>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_piece.hpp"

namespace arphys::collision {

class Shape {
 public:
  enum class Type { kPlane, kBox, kSphere, kMesh, kConvexSet };

  // The half-space z <= 0 of the body frame; its boundary is the plane z = 0.
  static Shape plane();
  // A box centred on the body origin, full side lengths in metres (each > 0).
  static Shape box(const Eigen::Vector3d& size_m);
  // A sphere centred on the body origin (radius > 0).
  static Shape sphere(double radius_m);
  static Shape mesh(std::shared_ptr<const CollisionMesh> mesh);
  static Shape convex_set(std::shared_ptr<const ConvexSet> pieces);

  Type type() const { return type_; }
  double radius_m() const { return radius_m_; }
  const Eigen::Vector3d& size_m() const { return size_m_; }
  // The triangle mesh of a box or a mesh shape, the pieces' hulls of a convex set; null
  // for planes and spheres.
  const CollisionMesh* triangles() const { return mesh_.get(); }
  // The convex pieces of a convex set, and a box's one piece; null otherwise.
  const ConvexSet* convex() const { return convex_.get(); }
  std::string describe() const;

 private:
  Type type_ = Type::kPlane;
  double radius_m_ = 0;
  Eigen::Vector3d size_m_ = Eigen::Vector3d::Zero();
  std::shared_ptr<const CollisionMesh> mesh_;
  std::shared_ptr<const ConvexSet> convex_;
};

}  // namespace arphys::collision
