#pragma once
// How well a set of convex pieces stands for the mesh it was made from: one-sided
// Hausdorff distances both ways between the solids (sampled on the surfaces: the
// largest distance of a solid's point from the other solid is reached on its boundary)
// and volumes (exact for the mesh and each piece, the pieces' union and its overlap
// with the mesh by exact vertical-column intervals on a grid).
#include <vector>

#include "simulator/collision/convex_piece.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::tools {

struct ApproximationError {
  double mesh_to_pieces_m = 0;   // furthest point of the mesh's solid outside every piece
  double pieces_to_mesh_m = 0;   // furthest point of a piece outside the mesh's solid
  double mesh_volume_m3 = 0;
  double pieces_volume_sum_m3 = 0;   // overlaps counted twice
  double union_volume_m3 = 0;        // of the pieces
  double intersection_volume_m3 = 0; // of the union with the mesh's solid
  int samples = 0;                   // surface points per side
};

// `mesh` must be closed (its inside is decided by ray parity); samples_per_side points on
// each surface, spread by area (seeded: the same answer every run); a grid of
// columns x columns over the bounding box for the volumes.
ApproximationError approximation_error(const geometry::TriangleMesh& mesh, const std::vector<collision::ConvexPiece>& pieces,
                                       int samples_per_side = 20000, int columns = 256);

}  // namespace arphys::tools
