#pragma once
#include <Eigen/Core>

#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::geometry {

// Mass, centre of mass and rotational inertia of a rigid body, in its body frame.
struct MassProperties {
  double mass_kg = 0;
  double volume_m3 = 0;
  Eigen::Vector3d center_of_mass_m = Eigen::Vector3d::Zero();
  // Inertia tensor about the centre of mass, axes of the body frame, kg m^2.
  Eigen::Matrix3d inertia_about_com_kg_m2 = Eigen::Matrix3d::Zero();
};

// Exact volume integration over a closed, consistently oriented triangle mesh
// (divergence theorem on the tetrahedra each triangle forms with the origin).
// An inward-oriented mesh (negative volume) is accepted and flipped.
// Throws std::invalid_argument when the mesh is not closed (cap its holes first
// with cap_boundary_loops) or has no volume, or density is not positive.
MassProperties mesh_mass_properties(const TriangleMesh& mesh, double density_kg_m3);

// Analytic solids centred on the body origin.
MassProperties box_mass_properties(const Eigen::Vector3d& size_m, double density_kg_m3);
MassProperties sphere_mass_properties(double radius_m, double density_kg_m3);

// The same shape at another mass (density = mass / volume).
MassProperties with_mass(const MassProperties& props, double mass_kg);

}  // namespace arphys::geometry
