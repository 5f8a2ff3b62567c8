#include "simulator/collision/collision_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace arphys::collision {

CollisionMesh::CollisionMesh(geometry::TriangleMesh mesh, bool test_each_feature_once)
    : mesh_(std::move(mesh)), tree_(mesh_) {
  // Edges shared by exactly two triangles with the same normal are flat.
  std::unordered_map<uint64_t, std::vector<Eigen::Vector3d>> normals;
  vertex_normals_.assign(mesh_.vertices_m.size(), Eigen::Vector3d::Zero());
  for (const auto& t : mesh_.triangles) {
    const Eigen::Vector3d n =
        (mesh_.vertices_m[t[1]] - mesh_.vertices_m[t[0]]).cross(mesh_.vertices_m[t[2]] - mesh_.vertices_m[t[0]]);
    if (!(n.norm() > 0)) continue;
    for (int k = 0; k < 3; ++k) {
      normals[edge_key(t[k], t[(k + 1) % 3])].push_back(n.normalized());
      // Weighted by the corner angle, so a face split into many triangles counts once.
      const Eigen::Vector3d e1 = mesh_.vertices_m[t[(k + 1) % 3]] - mesh_.vertices_m[t[k]];
      const Eigen::Vector3d e2 = mesh_.vertices_m[t[(k + 2) % 3]] - mesh_.vertices_m[t[k]];
      vertex_normals_[t[k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * n.normalized();
    }
  }
  for (const auto& [key, ns] : normals) {
    if (ns.size() == 2 && ns[0].dot(ns[1]) > 1 - 1e-12) flat_edges_.insert(key);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& n : ns) sum += n;
    edge_normals_[key] = sum;
  }
  owned_features_.assign(mesh_.triangles.size(), test_each_feature_once ? 0 : 0x3F);
  if (test_each_feature_once) {
    // Only triangles in the tree can stand for a feature: the tree leaves out degenerate
    // ones, and a vertex owned by one of those would never be tested.
    std::vector<int> in_tree;
    for (const ObbNode& node : tree_.nodes())
      if (node.is_leaf()) in_tree.push_back(node.triangle);
    std::sort(in_tree.begin(), in_tree.end());
    std::vector<bool> vertex_taken(mesh_.vertices_m.size(), false);
    std::unordered_set<uint64_t> edge_taken;
    for (const int i : in_tree) {
      const Eigen::Vector3i& t = mesh_.triangles[i];
      for (int k = 0; k < 3; ++k) {
        if (!vertex_taken[t[k]]) {
          vertex_taken[t[k]] = true;
          owned_features_[i] |= 1u << k;
        }
        const uint64_t key = edge_key(t[k], t[(k + 1) % 3]);
        if (!flat_edges_.count(key) && edge_taken.insert(key).second) owned_features_[i] |= 1u << (3 + k);
      }
    }
  }
  closed_ = geometry::mesh_topology(mesh_).closed();
}

std::shared_ptr<const CollisionMesh> CollisionMesh::load(const std::string& path, const Eigen::Vector3d& scale) {
  return std::make_shared<const CollisionMesh>(geometry::load_mesh(path, scale));
}

}  // namespace arphys::collision
