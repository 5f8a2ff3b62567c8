#pragma once
// A triangle mesh prepared for collision queries: the mesh (body frame, metres) and
// its OBB tree. Built once per model and shared by every body that uses it.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <string>
#include <vector>

#include "simulator/collision/obb_tree.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::collision {

class CollisionMesh {
 public:
  // test_each_feature_once: see owned_features (a box's mesh; not a scanned one).
  explicit CollisionMesh(geometry::TriangleMesh mesh, bool test_each_feature_once = false);
  CollisionMesh(const CollisionMesh&) = delete;  // the tree refers to mesh_
  CollisionMesh& operator=(const CollisionMesh&) = delete;

  // Loads a mesh file as it is (no rescaling, no recentring) and builds its tree.
  static std::shared_ptr<const CollisionMesh> load(const std::string& path,
                                                   const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

  const geometry::TriangleMesh& mesh() const { return mesh_; }
  const ObbTree& tree() const { return tree_; }
  // True for an edge between two coplanar triangles (a face's internal diagonal): it
  // is no feature of the surface, and contacts on it are those of the face.
  bool is_flat_edge(int v0, int v1) const { return flat_edges_.count(edge_key(v0, v1)) > 0; }
  // Closed (every edge shared by two triangles): then the triangles' counter-clockwise
  // normals point out of a solid, and contacts use them; an open surface (a shell, a
  // polygon soup) is two-sided and contacts take the side a feature is on.
  bool closed() const { return closed_; }
  // Sum of the unit normals of the triangles around a vertex (body frame): on a solid it
  // points out of the body at that vertex. Contacts use it to keep only the faces a
  // vertex can really rest on (not a neighbouring face it merely grazes).
  const Eigen::Vector3d& vertex_outward(int v) const { return vertex_normals_[v]; }
  // Sum of the unit normals of the triangles sharing an edge (body frame): on a solid
  // it points out of the body across that edge.
  Eigen::Vector3d edge_outward(int v0, int v1) const {
    const auto it = edge_normals_.find(edge_key(v0, v1));
    return it == edge_normals_.end() ? Eigen::Vector3d::Zero() : it->second;
  }

  // The features triangle i stands for in feature-pair tests (bits 0-2: its corner k;
  // bits 3-5: its edge from corner k to k + 1). With test_each_feature_once each vertex
  // and each edge belongs to one triangle, the first that has it, and a flat edge to
  // none: a continuous query then tests every vertex/face and edge/edge pair once, not
  // once per triangle around the vertex or beside the edge (a box corner three to six
  // times, an edge pair four times). Otherwise every triangle stands for all its features.
  // Why not for every mesh: two triangles touching to 1e-12 m at the start of a motion
  // can be culled by the OBB test (a triangle's box is flat) while a neighbouring pair
  // sharing the feature is not; the repeated tests made the touch found anyway. On a
  // scanned bunny one such pair went unseen and a pile of 100 bunnies diverged into a
  // worse squeeze. Boxes are safe by the separating-axis manifold and the overlap check
  // of the world step; a culling margin would make it safe for all (not done).
  uint8_t owned_features(int triangle) const { return owned_features_[triangle]; }

  // The three corners of triangle i, body frame.
  void corners(int triangle, Eigen::Vector3d out[3]) const {
    const Eigen::Vector3i& t = mesh_.triangles[triangle];
    for (int k = 0; k < 3; ++k) out[k] = mesh_.vertices_m[t[k]];
  }

 private:
  static uint64_t edge_key(int v0, int v1) {
    return (static_cast<uint64_t>(std::min(v0, v1)) << 32) | static_cast<uint32_t>(std::max(v0, v1));
  }

  geometry::TriangleMesh mesh_;
  ObbTree tree_;
  std::unordered_set<uint64_t> flat_edges_;
  std::unordered_map<uint64_t, Eigen::Vector3d> edge_normals_;
  std::vector<Eigen::Vector3d> vertex_normals_;
  std::vector<uint8_t> owned_features_;
  bool closed_ = false;
};

}  // namespace arphys::collision
