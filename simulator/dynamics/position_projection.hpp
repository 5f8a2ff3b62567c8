#pragma once
// Post-stabilisation (Cline & Pai, ICRA 2003): points that a step's candidate motion
// leaves too deep inside another body are lifted out by moving the end poses, not by
// changing velocities. A linearised contact lets a turning body's point dig in by a
// second-order amount (micrometres in a 1000-box pile at 1 ms); lifting it by a
// velocity constraint and solving the step again costs a solve of the whole island per
// round and leaves the body with the lift's speed, depth / step, millimetres per second
// for a micrometre. Here each point is lifted by the smallest mass-weighted move of the
// two bodies along its normal (a nonlinear Gauss-Seidel over the points, re-measured
// after every move), the minimum of ||dq||_M subject to the depth bounds, and
// velocities are left as the solve gave them: no energy is added.
#include <Eigen/Core>
#include <vector>

#include "simulator/geometry/pose.hpp"

namespace arphys::dynamics {

// A body as the projection moves it: its end pose, centre of mass (body frame), and
// inverse mass and world inverse inertia (zero for a body that does not move: static,
// kinematic).
struct ProjectedBody {
  geometry::Pose X_WB;
  Eigen::Vector3d center_of_mass_B = Eigen::Vector3d::Zero();
  double inverse_mass_1_kg = 0;
  Eigen::Matrix3d inverse_inertia_W = Eigen::Matrix3d::Zero();
};

// A point of body b held against body a: the material points on each surface (body
// frames) and a's outward normal there (a's frame). Its depth is how far b's point is
// behind a's along the normal; the projection brings it to at most target_depth_m.
struct ProjectedPoint {
  int body_a = -1, body_b = -1;  // indices into the bodies
  Eigen::Vector3d point_A_B, point_B_B, normal_A_B;
  double target_depth_m = 0;
};

struct ProjectionResult {
  int sweeps = 0;
  double worst_excess_m = 0;  // deepest point beyond its target after the last sweep
  bool converged = false;     // every point within its target plus tolerance_m
};

// Depth of a point at the bodies' poses (positive: inside).
double projected_depth_m(const std::vector<ProjectedBody>& bodies, const ProjectedPoint& point);

// Sweeps over the points, lifting each that is deeper than its target, until a sweep
// finds none deeper by more than tolerance_m (each measured as the sweep reaches it) or
// max_sweeps. Moves the poses of the bodies with inverse mass; the others stay bit for bit.
ProjectionResult project_points(std::vector<ProjectedBody>& bodies, const std::vector<ProjectedPoint>& points,
                                double tolerance_m, int max_sweeps);

}  // namespace arphys::dynamics
