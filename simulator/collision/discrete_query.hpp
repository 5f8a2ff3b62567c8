#pragma once
// Discrete (single pose) queries between two meshes: intersection, separation
// distance, and the contact manifold the dynamics uses for resting contact.
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/geometry/pose.hpp"

namespace arphys::collision {

struct TrianglePair {
  int triangle_A = -1, triangle_B = -1;
};

// A pair of intersecting (or exactly touching) triangles, if any.
std::optional<TrianglePair> find_intersection(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                              const geometry::Pose& X_WB);
inline bool intersects(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                       const geometry::Pose& X_WB) {
  return find_intersection(A, X_WA, B, X_WB).has_value();
}

struct SeparationResult {
  double distance_m = 0;  // 0 when the surfaces intersect
  Eigen::Vector3d point_A_W = Eigen::Vector3d::Zero(), point_B_W = Eigen::Vector3d::Zero();
  TrianglePair triangles;
};
// Smallest distance between the two surfaces. Pairs further apart than
// `max_distance_m` are not examined; when nothing is closer, distance_m is infinity.
SeparationResult separation(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                            const geometry::Pose& X_WB,
                            double max_distance_m = std::numeric_limits<double>::infinity());

struct ManifoldPoint {
  Eigen::Vector3d point_A_W, point_B_W;  // closest points, world, metres
  Eigen::Vector3d normal_W;              // unit, from A towards B
  double distance_m;                     // along the normal; negative where the bodies overlap
  TrianglePair triangles;
};
// The contact features closer than tolerance_m: each vertex over the interior of the
// other body's face (normal: that face's, oriented from A to B) and each pair of edges
// whose closest points lie inside both (normal: their common one), without
// duplicates. Two boxes stacked face to face give the corners of their overlap, which
// a stable resting contact needs. distance_m is measured along the normal.
std::vector<ManifoldPoint> contact_manifold(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                            const geometry::Pose& X_WB, double tolerance_m);

}  // namespace arphys::collision
