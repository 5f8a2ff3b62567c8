#pragma once
// Separating-axis tests between oriented boxes: static (with a margin, for the
// discrete queries and contact manifolds) and continuous, where box B moves relative
// to box A over a time interval and the 15 axis inequalities are evaluated in
// interval arithmetic (docs/method.md section 1.3). A "separated" answer is certain: the
// right-hand sides are rounded up with a proven bound and the left-hand sides are
// outward-rounded enclosures.
#include "simulator/collision/interval.hpp"
#include "simulator/collision/obb_tree.hpp"
#include "simulator/collision/screw_enclosure.hpp"

namespace arphys::collision {


// Continuous test over a time interval T = [tm - h, tm + h]: box A fixed in A's body
// frame, box B (given in B's body frame) placed in A's frame at tm by R_AB and the
// moving point `center` (its centre's position and velocity at tm), turning relative
// to A at `angular_speed` rad per unit t at most. In the mean-value form: along any
// axis L, every point of B stays within h (|L.v| + |L| (velocity_rad + angular_speed
// |half extents|)) of where it is at tm, so the boxes are disjoint over all of T when
// that sweep does not close the axis's gap at tm. True when certainly disjoint.
bool obbs_separated(const Obb& a, const Obb& b_in_B, const Eigen::Matrix3d& R_AB, const MovingPoint& center,
                    double angular_speed);
// Largest distance any point of box B can move over the interval (for time splitting).
double obb_sweep_m(const Obb& b_in_B, const MovingPoint& center, double angular_speed);

// Static test with a margin: true when the boxes, each grown by margin_m / 2 along its
// own axes, are disjoint, which proves their distance exceeds margin_m.
bool obbs_separated(const Obb& a, const Obb& b_in_B, const Eigen::Matrix3d& R_AB, const Eigen::Vector3d& p_AB,
                    double margin_m);

}  // namespace arphys::collision
