#pragma once
// Distance between two convex pieces by GJK (Gilbert, Johnson & Keerthi 1988) over the
// supports of their vertices. Every direction u the iteration visits proves a lower bound,
// the gap of the two pieces' supports along it; the iteration stops as soon as that bound
// exceeds what the caller needs, so proving two resting neighbours apart over a step
// costs a few support searches, not a sweep.
#include <limits>

#include "simulator/collision/convex_piece.hpp"
#include "simulator/geometry/pose.hpp"

namespace arphys::collision {

struct ConvexDistance {
  double lower_m = 0;   // a proven lower bound on the distance (<= 0: touching or overlapping)
  double upper_m = 0;   // the distance of the closest points found so far
  // Unit direction (world frame, from A towards B) along which the pieces' supports are
  // lower_m apart: a separating axis while lower_m > 0.
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitZ();
  int iterations = 0;
};

// Stops once lower_m > enough_m, or the bounds are within tolerance_m of each other, or the
// pieces are found to overlap (lower_m <= 0).
ConvexDistance convex_distance(const ConvexPiece& A, const geometry::Pose& X_WA, const ConvexPiece& B,
                               const geometry::Pose& X_WB, double enough_m = std::numeric_limits<double>::infinity(),
                               double tolerance_m = 1e-9);

// Whether every pair of the two sets' pieces is proven further apart than gap_m.
bool convex_sets_apart_by(const ConvexSet& A, const geometry::Pose& X_WA, const ConvexSet& B,
                          const geometry::Pose& X_WB, double gap_m);

}  // namespace arphys::collision
