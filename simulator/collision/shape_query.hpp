#pragma once
// Continuous collision between any two shapes (plane, box, sphere, mesh), each moving
// on its own screw motion from t = 0 to t = 1. Mesh and box pairs go to the mesh
// query; the plane and the sphere have their own certified tests: a mesh meets a
// half-space first at a vertex, a sphere meets anything when its centre comes within
// its radius. Same contract as the mesh query: never late, at most the tolerance
// early (in the sense documented there), nothing missed.
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/shape.hpp"

namespace arphys::collision {

// Throws std::invalid_argument for a plane against a plane (two unbounded boundaries:
// give one of them a box). Features are reported for mesh pairs only; the normal
// points from A towards B.
ContinuousResult time_of_impact(const Shape& A, const geometry::ScrewMotion& motion_A, const Shape& B,
                                const geometry::ScrewMotion& motion_B, const ContinuousOptions& options = {});

// Contact manifold at one pose: every feature pair closer than tolerance_m, with the
// closest points and the normal from A to B. For pairs with a plane or a sphere the
// distance is signed (negative: penetration depth); for mesh and box pairs it is the
// unsigned triangle distance, 0 where they intersect. Plane against plane throws.
// `nearby` serves the triangle mesh pairs (a mesh with a mesh or a box; not two boxes).
std::vector<ManifoldPoint> contact_manifold(const Shape& A, const geometry::Pose& X_WA, const Shape& B,
                                            const geometry::Pose& X_WB, double tolerance_m,
                                            NearbyTrianglePairs* nearby = nullptr);

}  // namespace arphys::collision
