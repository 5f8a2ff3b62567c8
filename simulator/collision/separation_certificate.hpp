#pragma once
// A cheap proof that two boxes on their screw motions stay apart for all t in [0, 1]:
// a face of one box that the other's eight vertices stay beyond the whole time (a
// separating axis that holds throughout the motion).
//
// Why: boxes resting on boxes (a pile, a stack) sit a micrometre apart and still move
// a little each step, so every step sends them to the CCD, whose search over their
// nearly coplanar faces costs 10 us to 10 ms per pair. This test costs well under a
// microsecond and settles most of those pairs.
//
// Contract: true only when the boxes cannot touch anywhere in [0, 1] (each vertex's
// height over the face is bounded below by its values at t = 0 and 1 minus a bound on
// its curvature, from the screw motions' angles and point speeds). False says nothing:
// the CCD then decides.
#include <Eigen/Core>

#include "simulator/collision/shape.hpp"
#include "simulator/geometry/screw_motion.hpp"

namespace arphys::collision {

// A lower bound on the distance between two boxes at fixed poses (metres; <= 0 says
// nothing): the largest gap along one of their six face normals. Two boxes this far apart
// cannot touch within a motion whose points move, relative to each other, by less: a
// test of a few dozen flops where the screw-motion proof above builds both motions.
double box_gap_lower_bound_m(const Eigen::Vector3d& half_extents_A_m, const geometry::Pose& X_WA,
                             const Eigen::Vector3d& half_extents_B_m, const geometry::Pose& X_WB);

// The same for any two shapes but planes (which give -1): the gap between their bounding
// boxes, a box itself, a mesh's root box, a sphere's cube.
double gap_lower_bound_m(const Shape& A, const geometry::Pose& X_WA, const Shape& B, const geometry::Pose& X_WB);

bool boxes_stay_apart(const Eigen::Vector3d& half_extents_A_m, const geometry::ScrewMotion& motion_A,
                      const Eigen::Vector3d& half_extents_B_m, const geometry::ScrewMotion& motion_B);

}  // namespace arphys::collision
