#pragma once
// The contact manifold of two boxes by the separating axis test and face clipping (as
// in ODE's dBoxBox and Gottschalk's OBB test): the axis of least penetration (or largest
// gap, up to the tolerance) among the 15 candidates is the one normal of every point.
// On a face axis the other box's most opposed face is clipped to the reference face,
// giving the corners of their overlap; on an edge-edge axis the two supporting edges'
// closest points. The triangle-mesh manifold answers "which features are close", and
// for two boxes overlapping by a few micrometres with nearly coplanar side faces it
// also reports the side faces, with opposed normals: a box squeezed from both sides by
// nothing (a tracked box pushing another one then let it fall through the floor).
#include <vector>

#include "simulator/collision/discrete_query.hpp"

namespace arphys::collision {

// size_A_m, size_B_m: full edge lengths. Points closer than tolerance_m (or overlapping);
// normal from A to B; distance_m along it (negative: overlap). triangles are -1.
std::vector<ManifoldPoint> box_box_manifold(const Eigen::Vector3d& size_A_m, const geometry::Pose& X_WA,
                                            const Eigen::Vector3d& size_B_m, const geometry::Pose& X_WB,
                                            double tolerance_m);

}  // namespace arphys::collision
