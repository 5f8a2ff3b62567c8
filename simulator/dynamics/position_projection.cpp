#include "simulator/dynamics/position_projection.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <stdexcept>

#include "simulator/dynamics/rigid_body.hpp"

namespace arphys::dynamics {

double projected_depth_m(const std::vector<ProjectedBody>& bodies, const ProjectedPoint& point) {
  const geometry::Pose& X_A = bodies[point.body_a].X_WB;
  const geometry::Pose& X_B = bodies[point.body_b].X_WB;
  return (X_A.linear() * point.normal_A_B).dot(X_A * point.point_A_B - X_B * point.point_B_B);
}

namespace {

// Moves a body's centre of mass by dx_W and turns it about its centre by dtheta_W.
void displace(ProjectedBody& body, const Eigen::Vector3d& dx_W, const Eigen::Vector3d& dtheta_W) {
  body.X_WB = moved_about_com(body.X_WB, body.center_of_mass_B, dx_W, dtheta_W, dtheta_W.norm());
}

}  // namespace

ProjectionResult project_points(std::vector<ProjectedBody>& bodies, const std::vector<ProjectedPoint>& points,
                                double tolerance_m, int max_sweeps) {
  if (!(tolerance_m > 0)) throw std::invalid_argument("project_points: tolerance_m must be positive, got " + std::to_string(tolerance_m));
  ProjectionResult result;
  for (; result.sweeps < max_sweeps; ++result.sweeps) {
    double worst = 0;
    for (const ProjectedPoint& p : points) {
      const double excess = projected_depth_m(bodies, p) - p.target_depth_m;
      worst = std::max(worst, excess);
      if (excess <= 0) continue;
      ProjectedBody& a = bodies[p.body_a];
      ProjectedBody& b = bodies[p.body_b];
      const Eigen::Vector3d n = a.X_WB.linear() * p.normal_A_B;
      const Eigen::Vector3d m = 0.5 * (a.X_WB * p.point_A_B + b.X_WB * p.point_B_B);
      const Eigen::Vector3d rn_a = (m - a.X_WB * a.center_of_mass_B).cross(n);
      const Eigen::Vector3d rn_b = (m - b.X_WB * b.center_of_mass_B).cross(n);
      // The point's depth changes by w per unit positional impulse along n.
      const double w = a.inverse_mass_1_kg + b.inverse_mass_1_kg + rn_a.dot(a.inverse_inertia_W * rn_a) +
                       rn_b.dot(b.inverse_inertia_W * rn_b);
      if (!(w > 0)) continue;  // both bodies fixed: nothing to move
      const double impulse = excess / w;
      // (A fixed body is left bit for bit where it is: the caller tells moved bodies by their poses.)
      if (a.inverse_mass_1_kg > 0) displace(a, -impulse * a.inverse_mass_1_kg * n, -impulse * (a.inverse_inertia_W * rn_a));
      if (b.inverse_mass_1_kg > 0) displace(b, impulse * b.inverse_mass_1_kg * n, impulse * (b.inverse_inertia_W * rn_b));
    }
    result.worst_excess_m = worst;
    if (worst <= tolerance_m) {
      result.converged = true;
      break;
    }
  }
  if (!result.converged) {
    double worst = 0;
    for (const ProjectedPoint& p : points) worst = std::max(worst, projected_depth_m(bodies, p) - p.target_depth_m);
    result.worst_excess_m = worst;
    result.converged = worst <= tolerance_m;
  }
  return result;
}

}  // namespace arphys::dynamics
