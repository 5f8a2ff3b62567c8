#include "simulator/collision/shape_query.hpp"

#include <gtest/gtest.h>

#include <random>

#include "simulator/collision/collision_mesh.hpp"
#include "tests/support/poses.hpp"
#include "tests/support/toi_checks.hpp"

namespace arphys::collision {
namespace {

using testing::at;
using testing::expect_toi;
using testing::kStill;
using geometry::Pose;
using geometry::ScrewMotion;

TEST(ShapeQuery, SphereOntoPlaneUnderTranslationAndScrew) {
  const Shape ground = Shape::plane(), ball = Shape::sphere(0.1);
  // Centre from z = 1 to -1: touches when z = 0.1, at t = 0.45.
  const auto r = time_of_impact(ground, kStill, ball, ScrewMotion(at({0.3, 0, 1}), at({0.3, 0, -1})));
  expect_toi(r, 0.45);
  EXPECT_NEAR(r.point_W.z(), 0.0, 1e-8);
  EXPECT_NEAR(r.normal_W.z(), 1.0, 1e-12);
  // A half turn about y moving the centre from (2, 0, c) to (-2, 0, c): the screw axis
  // is the y axis through (0, 0, c) and the centre dips along a circle of radius 2 to
  // z = c - 2 at t = 1/2 (Eigen's axis sign at exactly pi turns it downwards here).
  auto half_turn = [](double c) {
    return ScrewMotion(at({2, 0, c}), at({-2, 0, c}, Eigen::Vector3d::UnitY(), M_PI));
  };
  EXPECT_FALSE(time_of_impact(ground, kStill, ball, half_turn(2.3)).collides);   // lowest centre 0.3
  EXPECT_FALSE(time_of_impact(ground, kStill, ball, half_turn(2.101)).collides); // 0.101: a 1 mm near miss
  // Lowest centre 0.05: touches when 2.05 - 2 sin(pi t) = 0.1.
  const Pose Z0 = at({2, 0, 2.05}), Z1 = at({-2, 0, 2.05}, Eigen::Vector3d::UnitY(), M_PI);
  expect_toi(time_of_impact(ground, kStill, ball, ScrewMotion(Z0, Z1)), std::asin(1.95 / 2) / M_PI);
}

TEST(ShapeQuery, TiltedPlaneAndMirroredArguments) {
  // The plane tilted 30 deg about x; a sphere moving along -z from above its origin.
  const Pose tilt = at({0, 0, 0}, Eigen::Vector3d::UnitX(), M_PI / 6);
  const Shape ground = Shape::plane(), ball = Shape::sphere(0.1);
  // Centre (0, 0, z): distance to the plane = z cos 30; touch when z cos 30 = 0.1.
  const ScrewMotion fall(at({0, 0, 1}), at({0, 0, -1}));
  const double truth = (1 - 0.1 / std::cos(M_PI / 6)) / 2;
  const auto r = time_of_impact(ground, ScrewMotion(tilt, tilt), ball, fall);
  expect_toi(r, truth);
  const auto mirrored = time_of_impact(ball, fall, ground, ScrewMotion(tilt, tilt));
  expect_toi(mirrored, truth);
  EXPECT_NEAR((mirrored.normal_W + r.normal_W).norm(), 0.0, 1e-12);  // from A to B either way
}

TEST(ShapeQuery, BoxAndMeshOntoPlane) {
  const Shape ground = Shape::plane(), box = Shape::box({0.4, 0.2, 0.2});
  // Tilted 45 deg about x, the lowest corner is 0.1 sqrt(2) below the centre.
  const ScrewMotion fall(at({0, 0, 1}, Eigen::Vector3d::UnitX(), M_PI / 4), at({0, 0, -1}, Eigen::Vector3d::UnitX(), M_PI / 4));
  expect_toi(time_of_impact(ground, kStill, box, fall), (1 - 0.1 * std::sqrt(2.0)) / 2);
  auto mesh = std::make_shared<const CollisionMesh>(geometry::make_sphere_mesh(0.1, 2));
  double lowest = 0;
  for (const auto& v : mesh->mesh().vertices_m) lowest = std::min(lowest, v.z());
  const auto r = time_of_impact(ground, kStill, Shape::mesh(mesh), ScrewMotion(at({0, 0, 1}), at({0, 0, -1}, Eigen::Vector3d::UnitZ(), 2.0)));
  expect_toi(r, (1 + lowest) / 2);
  EXPECT_EQ(r.features.kind, FeaturePair::kPrimitive);
}

TEST(ShapeQuery, SphereAgainstSphereBothMoving) {
  const Shape a = Shape::sphere(0.1), b = Shape::sphere(0.2);
  // Head-on: centres 2 m apart closing at 2 m per step: touch at distance 0.3, t = 0.85.
  const auto r = time_of_impact(a, ScrewMotion(at({-1, 0, 0}), at({0, 0, 0})), b, ScrewMotion(at({1, 0, 0}), at({0, 0, 0})));
  expect_toi(r, 0.85);
  EXPECT_NEAR(r.point_W.x(), -0.15 + 0.1, 1e-8);
  EXPECT_NEAR(r.normal_W.x(), 1.0, 1e-9);
  EXPECT_FALSE(time_of_impact(a, kStill, b, ScrewMotion(at({1, 0.31, 0}), at({-1, 0.31, 0}))).collides);
  // A meeting with a point and a normal (a caller makes a constraint of it), not a
  // work budget's stop, which has neither.
  EXPECT_EQ(r.features.kind, FeaturePair::kPrimitive);
  EXPECT_FALSE(r.stats.budget_exhausted);
}

TEST(ShapeQuery, SphereAgainstBoxEdgeAndMeshFace) {
  const Shape box = Shape::box({0.2, 0.2, 0.2}), ball = Shape::sphere(0.05);
  // Centre along x at y = 0.12: passes the box's y = 0.1 side, meets the edge x = y = 0.1
  // when (x - 0.1)^2 + 0.02^2 = 0.05^2.
  const double x_touch = 0.1 + std::sqrt(0.05 * 0.05 - 0.02 * 0.02);
  expect_toi(time_of_impact(box, kStill, ball, ScrewMotion(at({1, 0.12, 0}), at({-1, 0.12, 0}))), (1 - x_touch) / 2);
  // Beyond y = 0.15 it misses.
  EXPECT_FALSE(time_of_impact(box, kStill, ball, ScrewMotion(at({1, 0.1501, 0}), at({-1, 0.1501, 0}))).collides);
  // Onto a flat mesh face, the box now spinning about z while the sphere falls.
  const auto r = time_of_impact(box, ScrewMotion(at({0, 0, 0}), at({0, 0, 0}, Eigen::Vector3d::UnitZ(), 1.0)), ball,
                                ScrewMotion(at({0.02, 0.01, 1}), at({0.02, 0.01, -1})));
  expect_toi(r, (1 - 0.15) / 2);
  EXPECT_NEAR(r.normal_W.z(), 1.0, 1e-6);
  EXPECT_EQ(r.features.kind, FeaturePair::kPrimitive);
}

// A box shape tests each vertex/face and edge/edge pair once (CollisionMesh's feature
// ownership) and is first offered to the separation certificate: over random tumbling
// motions near contact, its answer matches the plain triangle mesh of the same box,
// which tests every feature of every triangle pair.
TEST(ShapeQuery, BoxAgainstBoxAgreesWithItsPlainTriangleMesh) {
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  const Shape box = Shape::box(size);
  const CollisionMesh plain(geometry::make_box_mesh(size));
  std::mt19937 rng(1126);
  std::uniform_real_distribution<double> unit(-1, 1);
  auto pose = [&](const Eigen::Vector3d& centre, double angle_rad) {
    return at(centre, Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), angle_rad * unit(rng));
  };
  int meetings = 0, edge_edge = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Pose A0 = pose({0, 0, 0}, 1.5), A1 = pose({0.02 * unit(rng), 0.02 * unit(rng), 0.02 * unit(rng)}, 1.5);
    const Eigen::Vector3d start(0.25 * unit(rng), 0.25 * unit(rng), 0.25 + 0.05 * std::abs(unit(rng)));
    const Pose B0 = pose(start, 1.5), B1 = pose(0.3 * start - Eigen::Vector3d(0, 0, 0.02), 1.5);
    const ScrewMotion a(A0, A1), b(B0, B1);
    const ContinuousResult owned = time_of_impact(box, a, box, b);
    const ContinuousResult all = time_of_impact(plain, a, plain, b);
    ASSERT_EQ(owned.collides, all.collides) << "trial " << trial;
    if (!all.collides) continue;
    ++meetings;
    edge_edge += all.features.kind == FeaturePair::kEdgeEdge;
    EXPECT_NEAR(owned.time_of_impact, all.time_of_impact, 2e-9) << "trial " << trial;
  }
  // Not vacuous: many meetings, some first met edge to edge.
  EXPECT_GT(meetings, 100);
  EXPECT_GT(edge_edge, 10);
}

TEST(ShapeQuery, PlaneAgainstPlaneIsRejectedWithAReason) {
  try {
    time_of_impact(Shape::plane(), kStill, Shape::plane(), kStill);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("plane against plane"), std::string::npos);
  }
  EXPECT_THROW(Shape::sphere(-1), std::invalid_argument);
  EXPECT_THROW(Shape::box({0.1, 0, 0.1}), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::collision

namespace arphys::collision {
namespace {

TEST(ShapeManifold, BoxRestingOnPlaneGivesItsFourBottomCorners) {
  const Shape ground = Shape::plane(), box = Shape::box({0.4, 0.2, 0.2});
  const auto points = contact_manifold(ground, Pose::Identity(), box, at({0.3, 0.1, 0.1005}), 1e-3);
  ASSERT_EQ(points.size(), 4u);
  for (const auto& p : points) {
    EXPECT_NEAR(p.distance_m, 5e-4, 1e-12);
    EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-12);
    EXPECT_NEAR(p.point_A_W.z(), 0.0, 1e-12);
    EXPECT_NEAR(p.point_B_W.z(), 5e-4, 1e-12);
  }
  // Sunk 1 mm: signed distance -1 mm. With the plane as B the normal flips.
  const auto sunk = contact_manifold(box, at({0.3, 0.1, 0.099}), ground, Pose::Identity(), 1e-3);
  ASSERT_EQ(sunk.size(), 4u);
  EXPECT_NEAR(sunk[0].distance_m, -1e-3, 1e-12);
  EXPECT_NEAR(sunk[0].normal_W.z(), -1.0, 1e-12);
  // Tilted 45 degrees about x: one edge (two corners) touches.
  EXPECT_EQ(contact_manifold(ground, Pose::Identity(), box,
                             at({0, 0, 0.1 * std::sqrt(2.0)}, Eigen::Vector3d::UnitX(), M_PI / 4), 1e-6).size(), 2u);
  EXPECT_TRUE(contact_manifold(ground, Pose::Identity(), box, at({0, 0, 0.2}), 1e-3).empty());
}

TEST(ShapeManifold, SphereAgainstPlaneMeshAndSphere) {
  const Shape ground = Shape::plane(), ball = Shape::sphere(0.1), slab = Shape::box({2, 2, 0.1});
  const auto on_plane = contact_manifold(ground, Pose::Identity(), ball, at({1, 2, 0.098}), 1e-3);
  ASSERT_EQ(on_plane.size(), 1u);
  EXPECT_NEAR(on_plane[0].distance_m, -0.002, 1e-12);
  EXPECT_NEAR(on_plane[0].point_B_W.z(), -0.002, 1e-12);
  // On the slab's top face (z = 0.05): the closest triangles all give the same point.
  const auto on_slab = contact_manifold(slab, Pose::Identity(), ball, at({0.3, 0.2, 0.1505}), 1e-3);
  ASSERT_GE(on_slab.size(), 1u);
  for (const auto& p : on_slab) {
    EXPECT_NEAR(p.distance_m, 5e-4, 1e-12);
    EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-12);
    EXPECT_NEAR((p.point_A_W - Eigen::Vector3d(0.3, 0.2, 0.05)).norm(), 0.0, 1e-12);
  }
  const auto pair = contact_manifold(ball, at({0, 0, 0}), Shape::sphere(0.2), at({0.2995, 0, 0}), 1e-3);
  ASSERT_EQ(pair.size(), 1u);
  EXPECT_NEAR(pair[0].distance_m, -5e-4, 1e-12);
  EXPECT_NEAR(pair[0].normal_W.x(), 1.0, 1e-12);
  EXPECT_THROW(contact_manifold(ground, Pose::Identity(), ground, Pose::Identity(), 1e-3), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::collision
