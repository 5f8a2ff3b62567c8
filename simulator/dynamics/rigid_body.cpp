#include "simulator/dynamics/rigid_body.hpp"

#include <limits>

namespace arphys::dynamics {

Eigen::Matrix3d RigidBody::inverse_inertia_W() const {
  const Eigen::Matrix3d R = X_WB.linear();
  return R * mass.inertia_about_com_kg_m2.inverse() * R.transpose();
}

double RigidBody::kinetic_energy_J() const {
  if (!is_dynamic()) return 0;
  return 0.5 * mass.mass_kg * v_WC_m_s.squaredNorm() + 0.5 * w_W_rad_s.dot(inertia_W() * w_W_rad_s);
}

double RigidBody::bounding_radius_m() const {
  switch (shape.type()) {
    case collision::Shape::Type::kPlane: return std::numeric_limits<double>::infinity();
    case collision::Shape::Type::kSphere: return shape.radius_m();
    case collision::Shape::Type::kBox: return 0.5 * shape.size_m().norm();
    case collision::Shape::Type::kMesh: {
      double r = 0;
      for (const auto& v : shape.triangles()->mesh().vertices_m) r = std::max(r, v.norm());
      return r;
    }
  }
  return 0;
}

}  // namespace arphys::dynamics
