#include "simulator/collision/collision_mesh.hpp"

namespace arphys::collision {

std::shared_ptr<const CollisionMesh> CollisionMesh::load(const std::string& path, const Eigen::Vector3d& scale) {
  return std::make_shared<const CollisionMesh>(geometry::load_mesh(path, scale));
}

}  // namespace arphys::collision
