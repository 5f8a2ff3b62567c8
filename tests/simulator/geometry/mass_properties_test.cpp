#include "simulator/geometry/mass_properties.hpp"

#include <gtest/gtest.h>

#include "simulator/geometry/pose.hpp"

namespace arphys::geometry {
namespace {

TriangleMesh transformed(TriangleMesh mesh, const Pose& X) {
  for (auto& v : mesh.vertices_m) v = X * v;
  return mesh;
}

TEST(MassProperties, BoxMeshMatchesAnalyticBoxExactly) {
  const Eigen::Vector3d size(0.2, 0.3, 0.5);
  const MassProperties analytic = box_mass_properties(size, 800.0);
  const MassProperties integrated = mesh_mass_properties(make_box_mesh(size), 800.0);
  EXPECT_NEAR(integrated.volume_m3, 0.03, 1e-15);
  EXPECT_NEAR(integrated.mass_kg, analytic.mass_kg, 1e-12);
  EXPECT_LT(integrated.center_of_mass_m.norm(), 1e-15);
  EXPECT_LT((integrated.inertia_about_com_kg_m2 - analytic.inertia_about_com_kg_m2).norm(), 1e-13);
  // Textbook figure: 1 kg, 0.2 m cube -> I = m a^2 / 6 = 0.00666... kg m^2.
  const MassProperties cube = with_mass(box_mass_properties(Eigen::Vector3d::Constant(0.2), 1.0), 1.0);
  EXPECT_NEAR(cube.inertia_about_com_kg_m2(0, 0), 0.04 / 6.0, 1e-15);
}

TEST(MassProperties, MovedAndTurnedBoxHasRotatedInertiaAndShiftedCentre) {
  const Eigen::Vector3d size(0.1, 0.4, 0.2);
  const Pose X = translation_pose({1.5, -2, 0.7}) * rotation_pose({1, 2, 3}, 0.8);
  const MassProperties props = mesh_mass_properties(transformed(make_box_mesh(size), X), 1000.0);
  EXPECT_LT((props.center_of_mass_m - X.translation()).norm(), 1e-12);
  const Eigen::Matrix3d expected = X.linear() * box_mass_properties(size, 1000.0).inertia_about_com_kg_m2 * X.linear().transpose();
  EXPECT_LT((props.inertia_about_com_kg_m2 - expected).norm(), 1e-12);
}

TEST(MassProperties, InwardOrientedMeshIsFlipped) {
  TriangleMesh box = make_box_mesh({1, 1, 1});
  for (auto& t : box.triangles) std::swap(t[1], t[2]);
  EXPECT_NEAR(mesh_mass_properties(box, 1.0).volume_m3, 1.0, 1e-14);
}

TEST(MassProperties, SphereMeshConvergesToAnalyticSphere) {
  const MassProperties analytic = sphere_mass_properties(0.5, 1.0);
  double previous_error = 1.0;
  for (int subdivisions : {2, 4, 6}) {
    const MassProperties mesh = mesh_mass_properties(make_sphere_mesh(0.5, subdivisions), 1.0);
    const double error = std::abs(mesh.volume_m3 - analytic.volume_m3) / analytic.volume_m3;
    EXPECT_LT(error, previous_error / 10);  // second-order convergence: x16 per subdivision
    previous_error = error;
    EXPECT_LT(mesh.center_of_mass_m.norm(), 1e-12);
  }
  EXPECT_LT(previous_error, 1e-3);
  const MassProperties fine = mesh_mass_properties(make_sphere_mesh(0.5, 6), 1.0);
  EXPECT_NEAR(fine.inertia_about_com_kg_m2(1, 1) / analytic.inertia_about_com_kg_m2(1, 1), 1.0, 2e-3);
  EXPECT_NEAR(fine.inertia_about_com_kg_m2(0, 1), 0.0, 1e-9);
}

TEST(MassProperties, OpenMeshIsRejectedWithCounts) {
  TriangleMesh box = make_box_mesh({1, 1, 1});
  box.triangles.pop_back();
  try {
    mesh_mass_properties(box, 1.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("3 boundary"), std::string::npos) << e.what();
  }
}

TEST(MassProperties, PreconditionsNameTheValue) {
  try {
    box_mass_properties({0.1, -0.2, 0.1}, 1.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("-0.2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sphere_mass_properties(1.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::geometry
