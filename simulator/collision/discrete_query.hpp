#pragma once
// Discrete (single pose) queries between two meshes: intersection, separation
// distance, and the contact manifold the dynamics uses for resting contact.
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/geometry/pose.hpp"

namespace arphys::collision {

struct TrianglePair {
  int triangle_A = -1, triangle_B = -1;
};

// The leaf pairs of two meshes' trees (triangle pairs) whose boxes came within
// margin_m of each other at one relative pose, kept for the next queries of the same
// pair. A query asking for a margin m at a relative pose where no triangle of B has
// moved, relative to A, by margin_m - m or more tests only these pairs instead of
// descending both trees, and finds the same features in the same order: a pair it
// leaves out, or tests where a descent would not, is more than m apart, where no query
// finds anything. Otherwise the query descends the trees; when the pair barely moved
// since its last query (a quarter of spare_margin_m) it is likely to be queried nearby
// again, and the descent keeps what it finds with m + spare_margin_m. Bodies resting on
// each other are queried at nearly the same relative pose several times a step.
struct NearbyTrianglePairs {
  double spare_margin_m = 1e-3;
  const CollisionMesh* mesh_A = nullptr;
  const CollisionMesh* mesh_B = nullptr;
  bool seen = false;                                    // X_AB_seen: the last query's relative pose
  geometry::Pose X_AB_seen = geometry::Pose::Identity();
  geometry::Pose X_AB = geometry::Pose::Identity();     // where the kept leaves were found
  double margin_m = -1;                                 // with this margin (< 0: none kept)
  std::vector<std::pair<int32_t, int32_t>> leaves;      // node indices in A's and B's trees, in descent order
  int descents = 0, reuses = 0;
};

// A pair of intersecting (or exactly touching) triangles, if any.
std::optional<TrianglePair> find_intersection(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                              const geometry::Pose& X_WB, NearbyTrianglePairs* nearby = nullptr);
inline bool intersects(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                       const geometry::Pose& X_WB, NearbyTrianglePairs* nearby = nullptr) {
  return find_intersection(A, X_WA, B, X_WB, nearby).has_value();
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
                                            const geometry::Pose& X_WB, double tolerance_m,
                                            NearbyTrianglePairs* nearby = nullptr);

}  // namespace arphys::collision
