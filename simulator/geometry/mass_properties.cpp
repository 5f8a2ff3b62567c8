#include "simulator/geometry/mass_properties.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace arphys::geometry {
namespace {

void require_positive(double value, const char* name) {
  if (!(value > 0) || !std::isfinite(value)) {
    std::ostringstream s;
    s << name << " is " << value << ", expected a positive finite number";
    throw std::invalid_argument(s.str());
  }
}

}  // namespace

MassProperties mesh_mass_properties(const TriangleMesh& mesh, double density_kg_m3) {
  require_positive(density_kg_m3, "density_kg_m3");
  const MeshTopology topology = mesh_topology(mesh);
  if (!topology.closed()) {
    std::ostringstream s;
    s << "mesh_mass_properties needs a closed mesh; this one has " << topology.boundary_edges << " boundary and "
      << topology.non_manifold_edges << " non-manifold edges (cap holes with cap_boundary_loops)";
    throw std::invalid_argument(s.str());
  }
  // Per tetrahedron (0, a, b, c): signed volume V = a.(b x c)/6 and the second moment
  // C = V/20 (a a^T + b b^T + c c^T + (a+b+c)(a+b+c)^T) about the origin. Sum, then
  // shift to the centre of mass (parallel-axis on C) and convert C to the inertia tensor.
  // Vertices are first expressed relative to the mesh centroid to limit cancellation.
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();
  for (const auto& v : mesh.vertices_m) reference += v;
  reference /= static_cast<double>(mesh.vertices_m.size());

  double volume = 0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second_moment = Eigen::Matrix3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[t[0]] - reference;
    const Eigen::Vector3d b = mesh.vertices_m[t[1]] - reference;
    const Eigen::Vector3d c = mesh.vertices_m[t[2]] - reference;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d s = a + b + c;
    volume += v;
    first_moment += v * s / 4.0;
    second_moment += (v / 20.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  if (volume < 0) {  // inward-facing triangles: the same solid with all signs flipped
    volume = -volume;
    first_moment = -first_moment;
    second_moment = -second_moment;
  }
  if (!(volume > 0)) throw std::invalid_argument("mesh_mass_properties: the mesh encloses no volume");

  MassProperties props;
  props.volume_m3 = volume;
  props.mass_kg = density_kg_m3 * volume;
  const Eigen::Vector3d com_rel = first_moment / volume;
  props.center_of_mass_m = reference + com_rel;
  const Eigen::Matrix3d C = density_kg_m3 * (second_moment - volume * com_rel * com_rel.transpose());
  props.inertia_about_com_kg_m2 = C.trace() * Eigen::Matrix3d::Identity() - C;
  return props;
}

MassProperties box_mass_properties(const Eigen::Vector3d& size_m, double density_kg_m3) {
  require_positive(size_m.x(), "box size_m.x");
  require_positive(size_m.y(), "box size_m.y");
  require_positive(size_m.z(), "box size_m.z");
  require_positive(density_kg_m3, "density_kg_m3");
  MassProperties props;
  props.volume_m3 = size_m.prod();
  props.mass_kg = density_kg_m3 * props.volume_m3;
  const Eigen::Vector3d sq = size_m.cwiseProduct(size_m);
  props.inertia_about_com_kg_m2 =
      (props.mass_kg / 12.0) * Eigen::Vector3d(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()).asDiagonal();
  return props;
}

MassProperties sphere_mass_properties(double radius_m, double density_kg_m3) {
  require_positive(radius_m, "sphere radius_m");
  require_positive(density_kg_m3, "density_kg_m3");
  MassProperties props;
  props.volume_m3 = 4.0 / 3.0 * M_PI * radius_m * radius_m * radius_m;
  props.mass_kg = density_kg_m3 * props.volume_m3;
  props.inertia_about_com_kg_m2 = (0.4 * props.mass_kg * radius_m * radius_m) * Eigen::Matrix3d::Identity();
  return props;
}

MassProperties with_mass(const MassProperties& props, double mass_kg) {
  require_positive(mass_kg, "mass_kg");
  require_positive(props.mass_kg, "reference mass_kg");
  MassProperties out = props;
  const double ratio = mass_kg / props.mass_kg;
  out.mass_kg = mass_kg;
  out.inertia_about_com_kg_m2 *= ratio;
  return out;
}

}  // namespace arphys::geometry
