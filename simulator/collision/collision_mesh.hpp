#pragma once
// A triangle mesh prepared for collision queries: the mesh (body frame, metres) and
// its OBB tree. Built once per model and shared by every body that uses it.
#include <memory>
#include <string>

#include "simulator/collision/obb_tree.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::collision {

class CollisionMesh {
 public:
  explicit CollisionMesh(geometry::TriangleMesh mesh) : mesh_(std::move(mesh)), tree_(mesh_) {}
  CollisionMesh(const CollisionMesh&) = delete;  // the tree refers to mesh_
  CollisionMesh& operator=(const CollisionMesh&) = delete;

  // Loads a mesh file as it is (no rescaling, no recentring) and builds its tree.
  static std::shared_ptr<const CollisionMesh> load(const std::string& path,
                                                   const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

  const geometry::TriangleMesh& mesh() const { return mesh_; }
  const ObbTree& tree() const { return tree_; }
  // The three corners of triangle i, body frame.
  void corners(int triangle, Eigen::Vector3d out[3]) const {
    const Eigen::Vector3i& t = mesh_.triangles[triangle];
    for (int k = 0; k < 3; ++k) out[k] = mesh_.vertices_m[t[k]];
  }

 private:
  geometry::TriangleMesh mesh_;
  ObbTree tree_;
};

}  // namespace arphys::collision
