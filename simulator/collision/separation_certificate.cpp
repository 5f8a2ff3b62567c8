#include "simulator/collision/separation_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace arphys::collision {
namespace {

// Does face `axis` of A (the side facing B at t = 0) keep every vertex of B beyond it?
// With n(t) A's face normal, c(t) A's centre and p(t) a vertex of B, the vertex's height
// g(t) = n.(p - c) - h_A has g'' = n''.d + 2 n'.d' + n.d'' (d = p - c), where on screw
// motions |n'| <= theta_A, |n''| <= theta_A^2, every point moves along a helix at
// constant speed s with acceleration theta s, so |d''| <= theta_B s_p + theta_A s_c,
// |d'(t)| <= |d'(0)| + that, |d(t)| <= |d(0)| + |d'| bound. Then on [0, 1]
// g >= min(g(0), g(1)) - max|g''| / 8.
bool face_keeps_apart(const Eigen::Vector3d& half_A, const geometry::ScrewMotion& motion_A, int axis,
                      const Eigen::Vector3d& half_B, const geometry::ScrewMotion& motion_B) {
  const geometry::Pose& A0 = motion_A.start();
  const geometry::Pose& A1 = motion_A.end();
  const geometry::Pose& B0 = motion_B.start();
  const geometry::Pose& B1 = motion_B.end();
  const Eigen::Vector3d c0 = A0.translation(), c1 = A1.translation();
  Eigen::Vector3d n0 = A0.linear().col(axis), n1 = A1.linear().col(axis);
  if (n0.dot(B0.translation() - c0) < 0) {
    n0 = -n0;
    n1 = -n1;
  }
  const double theta_A = motion_A.angle_rad(), theta_B = motion_B.angle_rad();
  const Eigen::Vector3d v_c = motion_A.velocity_of_point(c0);
  const double s_c = v_c.norm();
  // Rounding in the heights (metres-sized coordinates) is far below this.
  constexpr double kMargin_m = 1e-12;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p_B((corner & 1 ? 1 : -1) * half_B.x(), (corner & 2 ? 1 : -1) * half_B.y(),
                              (corner & 4 ? 1 : -1) * half_B.z());
    const Eigen::Vector3d p0 = B0 * p_B, p1 = B1 * p_B;
    const double g0 = n0.dot(p0 - c0) - half_A[axis];
    const double g1 = n1.dot(p1 - c1) - half_A[axis];
    if (std::min(g0, g1) <= kMargin_m) return false;
    const Eigen::Vector3d v_p = motion_B.velocity_of_point(p0);
    const double d2 = theta_B * v_p.norm() + theta_A * s_c;
    const double d1 = (v_p - v_c).norm() + d2;
    const double d0 = (p0 - c0).norm() + d1;
    const double curvature = theta_A * theta_A * d0 + 2 * theta_A * d1 + d2;
    if (std::min(g0, g1) - curvature / 8 <= kMargin_m) return false;
  }
  return true;
}

}  // namespace

double box_gap_lower_bound_m(const Eigen::Vector3d& half_extents_A_m, const geometry::Pose& X_WA,
                             const Eigen::Vector3d& half_extents_B_m, const geometry::Pose& X_WB) {
  const Eigen::Vector3d d_W = X_WB.translation() - X_WA.translation();
  // R(i, k): A's axis i along B's axis k.
  const Eigen::Matrix3d R = X_WA.linear().transpose() * X_WB.linear();
  const Eigen::Matrix3d R_abs = R.cwiseAbs();
  const Eigen::Vector3d d_A = X_WA.linear().transpose() * d_W, d_B = X_WB.linear().transpose() * d_W;
  double gap = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    gap = std::max(gap, std::abs(d_A[i]) - half_extents_A_m[i] - R_abs.row(i).dot(half_extents_B_m));
    gap = std::max(gap, std::abs(d_B[i]) - half_extents_B_m[i] - R_abs.col(i).dot(half_extents_A_m));
  }
  return gap;
}

double gap_lower_bound_m(const Shape& A, const geometry::Pose& X_WA, const Shape& B, const geometry::Pose& X_WB) {
  // The shape's bounding box: its pose in the world and its half extents.
  const auto bounding_box = [](const Shape& shape, const geometry::Pose& X_WS, geometry::Pose& X_WO, Eigen::Vector3d& half_m) {
    switch (shape.type()) {
      case Shape::Type::kPlane:
        return false;
      case Shape::Type::kSphere:
        X_WO = X_WS;
        half_m.setConstant(shape.radius_m());
        return true;
      case Shape::Type::kBox:
        X_WO = X_WS;
        half_m = 0.5 * shape.size_m();
        return true;
      case Shape::Type::kMesh:
      case Shape::Type::kConvexSet: {
        const Obb& root = shape.triangles()->tree().root().box;
        geometry::Pose X_SO = geometry::Pose::Identity();
        X_SO.linear() = root.axes;
        X_SO.translation() = root.center;
        X_WO = X_WS * X_SO;
        half_m = root.half_extents_m;
        return true;
      }
    }
    return false;
  };
  geometry::Pose X_WOA, X_WOB;
  Eigen::Vector3d half_A, half_B;
  if (!bounding_box(A, X_WA, X_WOA, half_A) || !bounding_box(B, X_WB, X_WOB, half_B)) return -1;
  return box_gap_lower_bound_m(half_A, X_WOA, half_B, X_WOB);
}

bool boxes_stay_apart(const Eigen::Vector3d& half_extents_A_m, const geometry::ScrewMotion& motion_A,
                      const Eigen::Vector3d& half_extents_B_m, const geometry::ScrewMotion& motion_B) {
  for (int axis = 0; axis < 3; ++axis) {
    if (face_keeps_apart(half_extents_A_m, motion_A, axis, half_extents_B_m, motion_B)) return true;
    if (face_keeps_apart(half_extents_B_m, motion_B, axis, half_extents_A_m, motion_A)) return true;
  }
  return false;
}

}  // namespace arphys::collision
