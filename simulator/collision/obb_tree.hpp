#pragma once
// Oriented bounding box trees over triangle meshes (Gottschalk, Lin & Manocha,
// "OBBTree", SIGGRAPH 1996): boxes fitted to the area-weighted covariance of their
// triangles, split top-down at the mean centroid along the longest box axis.
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::collision {

struct Obb {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();         // body frame, metres
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();       // columns: unit box axes in the body frame
  Eigen::Vector3d half_extents_m = Eigen::Vector3d::Zero();
  double radius_m = 0;  // |half_extents_m|: the bounding sphere's radius about the center
};

struct ObbNode {
  Obb box;
  int32_t first_child = -1;  // children at first_child and first_child + 1; -1 for a leaf
  int32_t triangle = -1;     // leaf: index into the mesh's triangles
  bool is_leaf() const { return first_child < 0; }
};

class ObbTree {
 public:
  // Builds the tree over every non-degenerate triangle of `mesh` (a polygon soup is
  // fine: no topology is assumed). Triangles with an area below
  // 1e-12 x (bounding-box diagonal)^2, or with a repeated vertex index, are skipped
  // and counted. Throws std::invalid_argument when no triangle is left.
  explicit ObbTree(const geometry::TriangleMesh& mesh);

  const std::vector<ObbNode>& nodes() const { return nodes_; }
  const ObbNode& root() const { return nodes_[0]; }
  std::size_t degenerate_triangles_skipped() const { return degenerate_skipped_; }
  int depth() const { return depth_; }
  // The farthest any point of any node's box lies from the root box's centre: bounds
  // how far a turn about that centre can move any of the tree's triangles.
  double reach_m() const { return reach_m_; }

 private:
  void build(int node, std::vector<int>& triangles, int begin, int end, int depth);

  const geometry::TriangleMesh* mesh_;
  std::vector<ObbNode> nodes_;
  std::size_t degenerate_skipped_ = 0;
  int depth_ = 0;
  double reach_m_ = 0;
};

// Box fitted to a set of triangles: axes from the eigenvectors of the covariance of
// the triangle surfaces (area-weighted), extents from the vertices.
Obb fit_obb(const geometry::TriangleMesh& mesh, const int* triangles, int count);

}  // namespace arphys::collision
