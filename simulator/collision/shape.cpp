#include "simulator/collision/shape.hpp"

#include <cmath>
#include <stdexcept>

namespace arphys::collision {

Shape Shape::plane() { return Shape(); }

Shape Shape::box(const Eigen::Vector3d& size_m) {
  if (!(size_m.minCoeff() > 0) || !size_m.allFinite())
    throw std::invalid_argument("Shape::box: every side must be a positive, finite length in metres; got " +
                                std::to_string(size_m.x()) + " x " + std::to_string(size_m.y()) + " x " +
                                std::to_string(size_m.z()));
  Shape s;
  s.type_ = Type::kBox;
  s.size_m_ = size_m;
  s.mesh_ = std::make_shared<const CollisionMesh>(geometry::make_box_mesh(size_m), /*test_each_feature_once=*/true);
  std::vector<ConvexPiece> piece;
  piece.emplace_back(geometry::make_box_mesh(size_m));
  s.convex_ = make_convex_set(std::move(piece));
  return s;
}

Shape Shape::sphere(double radius_m) {
  if (!(radius_m > 0) || !std::isfinite(radius_m))
    throw std::invalid_argument("Shape::sphere: radius_m must be positive and finite; got " + std::to_string(radius_m));
  Shape s;
  s.type_ = Type::kSphere;
  s.radius_m_ = radius_m;
  return s;
}

Shape Shape::mesh(std::shared_ptr<const CollisionMesh> mesh) {
  if (!mesh) throw std::invalid_argument("Shape::mesh: null mesh");
  Shape s;
  s.type_ = Type::kMesh;
  s.mesh_ = std::move(mesh);
  return s;
}

Shape Shape::convex_set(std::shared_ptr<const ConvexSet> pieces) {
  if (!pieces || pieces->pieces.empty() || !pieces->hulls) throw std::invalid_argument("Shape::convex_set: no pieces");
  Shape s;
  s.type_ = Type::kConvexSet;
  s.mesh_ = pieces->hulls;
  s.convex_ = std::move(pieces);
  return s;
}

std::string Shape::describe() const {
  switch (type_) {
    case Type::kPlane: return "plane";
    case Type::kBox: return "box";
    case Type::kSphere: return "sphere";
    case Type::kMesh: return "mesh (" + std::to_string(mesh_->mesh().num_triangles()) + " triangles)";
    case Type::kConvexSet:
      return "convex set (" + std::to_string(convex_->pieces.size()) + " pieces, " +
             std::to_string(mesh_->mesh().num_vertices()) + " vertices)";
  }
  return "?";
}

}  // namespace arphys::collision
