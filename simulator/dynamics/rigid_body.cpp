#include "simulator/dynamics/rigid_body.hpp"

#include <limits>

namespace arphys::dynamics {

Eigen::Matrix3d inertia_W(const BodyModel& m, const BodyState& s) {
  const Eigen::Matrix3d R = s.X_WB.linear();
  return R * m.mass.inertia_about_com_kg_m2 * R.transpose();
}

Eigen::Matrix3d inverse_inertia_W(const BodyModel& m, const BodyState& s) {
  const Eigen::Matrix3d R = s.X_WB.linear();
  return R * m.mass.inertia_about_com_kg_m2.inverse() * R.transpose();
}

double kinetic_energy_J(const BodyModel& m, const BodyState& s) {
  if (!m.is_dynamic()) return 0;
  return 0.5 * m.mass.mass_kg * s.v_WBcm_m_s.squaredNorm() + 0.5 * s.w_WB_rad_s.dot(inertia_W(m, s) * s.w_WB_rad_s);
}

geometry::Pose moved_about_com(const geometry::Pose& X_WB, const Eigen::Vector3d& com_B,
                               const Eigen::Vector3d& com_shift_W, const Eigen::Vector3d& turn_axis_W, double turn_rad) {
  Eigen::Matrix3d R = X_WB.linear();
  if (turn_rad > 0) R = Eigen::AngleAxisd(turn_rad, turn_axis_W.normalized()).toRotationMatrix() * R;
  R = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  geometry::Pose X = geometry::Pose::Identity();
  X.linear() = R;
  X.translation() = X_WB * com_B + com_shift_W - R * com_B;
  return X;
}

double BodyModel::bounding_radius_m() const {
  switch (shape.type()) {
    case collision::Shape::Type::kPlane: return std::numeric_limits<double>::infinity();
    case collision::Shape::Type::kSphere: return shape.radius_m();
    case collision::Shape::Type::kBox: return 0.5 * shape.size_m().norm();
    case collision::Shape::Type::kMesh:
    case collision::Shape::Type::kConvexSet: {
      double r = 0;
      for (const auto& v : shape.triangles()->mesh().vertices_m) r = std::max(r, v.norm());
      return r;
    }
  }
  return 0;
}

}  // namespace arphys::dynamics
