#pragma once
// Broad phase for many bodies over a time step: each body's swept axis-aligned box
// (its bounding sphere carried along its screw motion), then sweep-and-prune along x
// within cells of a grid over y and z, to find the pairs whose swept boxes overlap.
// Only those go to the narrow phase.
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

// The overlapping pairs (i < j, sorted) with at least one box in `selected` (one flag
// per box): those boxes are tested against all, or, when they are many (beyond an
// eighth), the full sweep's answer is filtered. For the re-solves of a step, which
// change a few bodies' motions among many (sweeping every box of a 1000-box pile again
// was a twentieth of its step).
std::vector<std::pair<int, int>> overlapping_pairs_involving(const std::vector<Eigen::AlignedBox3d>& boxes,
                                                             const std::vector<char>& selected);

// The same answer as overlapping_pairs(boxes), given its answer `before` for boxes that
// differed only where `changed` is set: the pairs of unchanged boxes carry over, the
// changed boxes' pairs are found by overlapping_pairs_involving.
std::vector<std::pair<int, int>> overlapping_pairs_updated(const std::vector<Eigen::AlignedBox3d>& boxes,
                                                           const std::vector<char>& changed,
                                                           const std::vector<std::pair<int, int>>& before);

}  // namespace arphys::collision
