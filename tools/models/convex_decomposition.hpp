#pragma once
// Approximate convex decomposition of a triangle mesh, offline: Bullet extras' HACD
// (Mamou & Ghorbel 2009, hierarchical clustering of the mesh's dual graph by concavity)
// finds the clusters and their simplified hulls; qhull then takes each cluster's hull
// anew, so every piece is an exactly convex, outward-wound, closed triangle mesh that
// collision::ConvexPiece accepts.
#include <string>
#include <vector>

#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::tools {

struct DecompositionOptions {
  int min_pieces = 8;                // HACD stops merging clusters at this many
  double max_concavity = 0.1;        // relative to the mesh's bounding-box diagonal
  int max_vertices_per_piece = 32;   // HACD simplifies each hull to at most this many
};

// The pieces (body frame of the mesh). Throws std::runtime_error when HACD or qhull fail.
std::vector<geometry::TriangleMesh> decompose_convex(const geometry::TriangleMesh& mesh,
                                                     const DecompositionOptions& options);

// The convex hull of the points as a closed triangle mesh, wound outward (qhull).
// Throws std::runtime_error for fewer than 4 points or a flat set.
geometry::TriangleMesh convex_hull(const std::vector<Eigen::Vector3d>& points);

}  // namespace arphys::tools
