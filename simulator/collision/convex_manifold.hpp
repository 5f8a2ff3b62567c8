#pragma once
// Contact manifolds of convex pieces (convex_piece.hpp) by separating axes, as
// box_box_manifold does for boxes and Gregorius (GDC 2013) for any polyhedra: the face
// normals of both pieces and the cross products of the edge pairs that form faces of
// their Minkowski difference (Gauss map arcs that cross). The axis of least penetration,
// or of largest gap up to the tolerance, is the one normal of the pair: on a face axis
// the other piece's most opposed face is clipped to the reference face, giving the corners
// of their overlap; on an edge axis the two edges' closest points. Distances are signed
// (negative: overlap), so a pair's depth is measured, as for primitives.
#include <vector>

#include "simulator/collision/convex_piece.hpp"
#include "simulator/collision/discrete_query.hpp"

namespace arphys::collision {

// Appends the points of pieces A and B closer than tolerance_m (or overlapping), normal
// from A to B. Each point's `triangles` holds the two pieces' indices given here.
void convex_manifold(const ConvexPiece& A, int index_A, const geometry::Pose& X_WA, const ConvexPiece& B, int index_B,
                     const geometry::Pose& X_WB, double tolerance_m, std::vector<ManifoldPoint>* points);

// Every piece pair of two sets whose bounding balls come within tolerance_m.
std::vector<ManifoldPoint> convex_set_manifold(const ConvexSet& A, const geometry::Pose& X_WA, const ConvexSet& B,
                                               const geometry::Pose& X_WB, double tolerance_m);

// The set's vertices within tolerance_m of (or below) the plane z = 0 of the plane body
// (A), normal along the plane's +z.
std::vector<ManifoldPoint> plane_convex_set_manifold(const geometry::Pose& X_WA, const ConvexSet& B,
                                                     const geometry::Pose& X_WB, double tolerance_m);

// A sphere (B, radius_m about its origin) against the set's pieces (A): one point per
// piece within reach, signed (a centre inside a piece is as deep as its nearest face).
std::vector<ManifoldPoint> convex_set_sphere_manifold(const ConvexSet& A, const geometry::Pose& X_WA, double radius_m,
                                                      const geometry::Pose& X_WB, double tolerance_m);

// A convex polygon clipped to the half space n.x <= offset (Sutherland-Hodgman).
std::vector<Eigen::Vector3d> clip_to_half_space(const std::vector<Eigen::Vector3d>& polygon, const Eigen::Vector3d& n,
                                                double offset);

// Signed distance from a point (the piece's frame) to the piece: negative inside.
double signed_distance(const ConvexPiece& piece, const Eigen::Vector3d& p, Eigen::Vector3d* closest = nullptr,
                       Eigen::Vector3d* normal = nullptr);

}  // namespace arphys::collision
