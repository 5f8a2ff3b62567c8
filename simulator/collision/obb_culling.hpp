#pragma once
// Separating-axis tests between oriented boxes: static (with a margin, for the
// discrete queries and contact manifolds) and continuous, where box B moves relative
// to box A over a time interval and the 15 axis inequalities are evaluated in
// interval arithmetic (METHOD.md section 1.3). A "separated" answer is certain: the
// right-hand sides are rounded up with a proven bound and the left-hand sides are
// outward-rounded enclosures.
#include "simulator/collision/interval.hpp"
#include "simulator/collision/obb_tree.hpp"

namespace arphys::collision {


// Continuous test: box B (given in B's body frame) placed in A's body frame by the
// enclosures R_AB of its rotation and b_center_A of its center over a time interval.
// True when the boxes are certainly disjoint at every time of that interval. The 15
// inequalities are evaluated in midpoint-radius interval arithmetic, which avoids the
// dependency blow-up of chained interval matrix products; its rounding is covered by a
// relative slack of 1e-13 on every comparison (each side is a sum of at most 12
// products of non-negative bounds, whose computed value is within 30 ulps).
bool obbs_separated(const Obb& a, const Obb& b_in_B, const MidRadMatrix& R_AB, const MidRadVector& b_center_A);

// Static test with a margin: true when the boxes, each grown by margin_m / 2 along its
// own axes, are disjoint, which proves their distance exceeds margin_m.
bool obbs_separated(const Obb& a, const Obb& b_in_B, const Eigen::Matrix3d& R_AB, const Eigen::Vector3d& p_AB,
                    double margin_m);

}  // namespace arphys::collision
