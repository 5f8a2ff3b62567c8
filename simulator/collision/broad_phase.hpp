#pragma once
// Broad phase for many bodies over a time step: each body's swept axis-aligned box
// (its bounding sphere carried along its screw motion), then sweep-and-prune along x,
// within strips along y, to find the pairs whose swept boxes overlap. Only those go to
// the narrow phase.
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "simulator/geometry/screw_motion.hpp"

namespace arphys::collision {

// World box containing the ball of `radius_m` about the body point `center_B` at every
// t in [0, 1] of `motion` (certified, in closed form: the screw path's arc about its
// axis stays within its sagitta of the chord). An unbounded body (a plane) gets an
// infinite box.
Eigen::AlignedBox3d swept_bounds(const geometry::ScrewMotion& motion, const Eigen::Vector3d& center_B, double radius_m);

// Index pairs (i < j) whose boxes overlap, sorted. Boxes may be infinite or empty; one
// with a NaN coordinate overlaps nothing.
std::vector<std::pair<int, int>> overlapping_pairs(const std::vector<Eigen::AlignedBox3d>& boxes);

}  // namespace arphys::collision
