#include "simulator/collision/continuous_query.hpp"

#include <gtest/gtest.h>

#include <random>

#include "simulator/collision/discrete_query.hpp"
#include "tests/support/poses.hpp"
#include "tests/support/toi_checks.hpp"

namespace arphys::collision {
namespace {

using testing::at;
using testing::expect_toi;
using testing::kStill;
using testing::random_vector;
using geometry::Pose;
using geometry::ScrewMotion;

Pose at(double x, double y, double z) { return geometry::translation_pose({x, y, z}); }

// A 2 x 2 x 0.1 m slab whose top face is z = 0 (the "table").
CollisionMesh slab() {
  auto mesh = geometry::make_box_mesh({2, 2, 0.1});
  for (auto& v : mesh.vertices_m) v.z() -= 0.05;
  return CollisionMesh(std::move(mesh));
}

TEST(ContinuousQuery, CubeFallingOnSlabUnderTranslation) {
  const CollisionMesh table = slab(), cube(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  // Center from z = 1.0 to -0.5: bottom face (center - 0.1) meets z = 0 at t = 0.6.
  const auto r = time_of_impact(table, kStill, cube, ScrewMotion(at(0.1, 0.2, 1.0), at(0.1, 0.2, -0.5)));
  expect_toi(r, 0.6);
  EXPECT_NEAR(r.point_W.z(), 0.0, 1e-8);
  EXPECT_NEAR(r.normal_W.z(), 1.0, 1e-9);  // from the table (A) up towards the cube (B)
}

TEST(ContinuousQuery, SphereScrewingDownOntoSlab) {
  // Rotation about the vertical axis does not change vertex heights, so the TOI is the
  // lowest vertex's height over the descent, in closed form, while the screw turns 170 deg.
  const CollisionMesh table = slab();
  const auto sphere_mesh = geometry::make_sphere_mesh(0.1, 2);
  double lowest = 0;
  for (const auto& v : sphere_mesh.vertices_m) lowest = std::min(lowest, v.z());
  const CollisionMesh sphere(sphere_mesh);
  const ScrewMotion screw(at({0, 0, 0.5}, Eigen::Vector3d::UnitZ(), 0.0),
                          at({0, 0, -0.3}, Eigen::Vector3d::UnitZ(), 170 * M_PI / 180));
  const double truth = (0.5 + lowest) / 0.8;
  expect_toi(time_of_impact(table, kStill, sphere, screw), truth);
}

TEST(ContinuousQuery, BoxTippingOverOntoSlabMatchesTheCornerTrajectory) {
  // A 0.4 x 0.2 x 0.2 box turns 90 deg about x while dropping 0.2 m. Its screw axis is
  // parallel to x but offset (the drop is absorbed into a rotation about it), so the
  // corners follow circles: the truth is the first root of the lowest corner's height
  // along geometry::ScrewMotion::pose_at, bisected here without any CCD code.
  const auto box_mesh = geometry::make_box_mesh({0.4, 0.2, 0.2});
  const CollisionMesh table = slab(), box(box_mesh);
  const ScrewMotion screw(at({0, 0, 0.35}, Eigen::Vector3d::UnitX(), 0.0),
                          at({0, 0, 0.05}, Eigen::Vector3d::UnitX(), M_PI / 2));
  auto lowest_corner = [&](double t) {
    double low = 1e9;
    for (const auto& v : box_mesh.vertices_m) low = std::min(low, (screw.pose_at(t) * v).z());
    return low;
  };
  double lo = 0, hi = 1;
  ASSERT_LT(lowest_corner(1.0), 0.0);
  for (int i = 0; i < 200; ++i) ((lowest_corner(0.5 * (lo + hi)) > 0) ? lo : hi) = 0.5 * (lo + hi);
  const auto r = time_of_impact(table, kStill, box, screw);
  expect_toi(r, hi);
  EXPECT_NEAR(r.point_W.z(), 0.0, 1e-8);
}

TEST(ContinuousQuery, ThinPlateFlyingThroughThinPlateIsCaught) {
  // Zero-thickness plates: A is 1 x 1 m, B is 0.3 x 0.3 m tilted 10 deg (0.052 m tall).
  // B falls 10 m in one step while spinning 60 deg about the vertical: it is inside A's
  // plane for 0.5 % of the step, so sampling with 10 or 50 steps tunnels through.
  geometry::TriangleMesh plate;
  plate.vertices_m = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
  plate.triangles = {{0, 1, 2}, {0, 2, 3}};
  const CollisionMesh A(plate);
  geometry::TriangleMesh tilted = plate;
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (auto& v : tilted.vertices_m) v = tilt * (0.3 * v);
  const CollisionMesh B(tilted);
  const ScrewMotion fly(at({0.0, 0.02, 5.1}, Eigen::Vector3d::UnitZ(), 0.0),
                        at({0.0, 0.02, -4.9}, Eigen::Vector3d::UnitZ(), M_PI / 3));
  // Turning about the vertical does not change heights: B's lowest corner (0.15 sin 10
  // deg below its centre) reaches z = 0 when 5.1 - 10 t = 0.15 sin(10 deg).
  const auto r = time_of_impact(A, kStill, B, fly);
  expect_toi(r, (5.1 - 0.15 * std::sin(10 * M_PI / 180)) / 10);
  for (int n : {10, 50}) {
    bool caught = false;
    for (int k = 0; k <= n && !caught; ++k)
      caught = intersects(A, Pose::Identity(), B, fly.pose_at(static_cast<double>(k) / n));
    EXPECT_FALSE(caught) << "discrete sampling with " << n << " steps should tunnel here";
  }
}

TEST(ContinuousQuery, ParallelEdgesAndCoplanarFacesAlignedBoxes) {
  // Two axis-aligned cubes approaching face to face: every contact feature pair is
  // degenerate (parallel edges, coplanar faces, vertices on edges).
  const CollisionMesh a(geometry::make_box_mesh({0.2, 0.2, 0.2})), b(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  const auto r = time_of_impact(a, kStill, b, ScrewMotion(at(1.0, 0.0, 0.0), at(0.0, 0.0, 0.0)));
  expect_toi(r, 0.8);
  EXPECT_NEAR(r.point_W.x(), 0.1, 1e-8);
  EXPECT_NEAR(r.normal_W.x(), 1.0, 1e-6);  // A is at the origin, B comes from +x
  // Offset by exactly one edge length in y: the cubes slide along each other's faces,
  // edge on edge, and touch all along (at distance 0 from t = 0.8).
  expect_toi(time_of_impact(a, kStill, b, ScrewMotion(at(1.0, 0.2, 0.0), at(0.0, 0.2, 0.0))), 0.8);
  // Just beyond: a near miss by 1e-6 m.
  EXPECT_FALSE(time_of_impact(a, kStill, b, ScrewMotion(at(1.0, 0.200001, 0.0), at(0.0, 0.200001, 0.0))).collides);
}

TEST(ContinuousQuery, ContactAtStartAndTouchingAtTheEnd) {
  const CollisionMesh table = slab(), cube(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  const auto overlap = time_of_impact(table, kStill, cube, ScrewMotion(at(0, 0, 0.05), at(0, 0, 1.0)));
  ASSERT_TRUE(overlap.collides);
  EXPECT_EQ(overlap.time_of_impact, 0.0);
  EXPECT_EQ(overlap.features.kind, FeaturePair::kOverlapAtStart);
  // Ends exactly touching (bottom face at z = 0 at t = 1).
  const auto touch = time_of_impact(table, kStill, cube, ScrewMotion(at(0.3, 0, 1.1), at(0.3, 0, 0.1)));
  expect_toi(touch, 1.0);
  // Stops 1 mm short.
  EXPECT_FALSE(time_of_impact(table, kStill, cube, ScrewMotion(at(0.3, 0, 1.1), at(0.3, 0, 0.101))).collides);
}

TEST(ContinuousQuery, RotationNearZeroAndNearPi) {
  const CollisionMesh table = slab(), cube(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  // Turning about the vertical axis keeps the bottom face at center - 0.1: TOI 0.6.
  for (double angle : {1e-13, 1e-7, M_PI - 1e-9, M_PI}) {
    const auto r = time_of_impact(table, kStill, cube,
                                  ScrewMotion(at({0, 0, 1.0}, Eigen::Vector3d::UnitZ(), 0.0),
                                              at({0, 0, -0.5}, Eigen::Vector3d::UnitZ(), angle)));
    expect_toi(r, 0.6);
  }
}

TEST(ContinuousQuery, ResultDoesNotDependOnTheWorldFrame) {
  // The same scene expressed in another world frame W must give the same TOI.
  const CollisionMesh a(geometry::make_sphere_mesh(0.2, 2)), b(geometry::make_box_mesh({0.3, 0.1, 0.2}));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 30; ++i) {
    // (Drawn in a fixed order: the order of a call's arguments is the compiler's.)
    const Eigen::Vector3d p0{u(rng), u(rng), u(rng)}, axis0 = random_vector(rng);
    const double angle0 = u(rng) * 3;
    const Eigen::Vector3d p1{u(rng) * 0.2, u(rng) * 0.2, u(rng) * 0.2}, axis1 = random_vector(rng);
    const double angle1 = u(rng) * 3;
    const Pose XB0 = at(p0, axis0, angle0);
    const Pose XB1 = at(p1, axis1, angle1);
    if (intersects(a, Pose::Identity(), b, XB0)) continue;
    const auto still = time_of_impact(a, kStill, b, ScrewMotion(XB0, XB1));
    const Pose W = at({0.5, -0.2, 0.3}, Eigen::Vector3d::UnitY(), 0.7);
    const auto moved = time_of_impact(a, ScrewMotion(W, W), b, ScrewMotion(W * XB0, W * XB1));
    ASSERT_EQ(still.collides, moved.collides) << i;
    if (still.collides) {
      ++hits;
      EXPECT_NEAR(still.time_of_impact, moved.time_of_impact, 2e-9) << i;
    }
  }
  EXPECT_GT(hits, 5);
}

// A caller that found the meshes apart at the start poses may skip the query's own start
// test: the answer is the same, to the bit (the motions do meet, in some cases).
TEST(ContinuousQuery, ApartAtStartSkipsOnlyTheStartTest) {
  const CollisionMesh a(geometry::make_sphere_mesh(0.2, 2)), b(geometry::make_box_mesh({0.3, 0.1, 0.2}));
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  int compared = 0, hits = 0;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3d p0{u(rng), u(rng), u(rng)}, axis0 = random_vector(rng);
    const double angle0 = u(rng) * 3;
    const Eigen::Vector3d p1{u(rng) * 0.2, u(rng) * 0.2, u(rng) * 0.2}, axis1 = random_vector(rng);
    const double angle1 = u(rng) * 3;
    const ScrewMotion motion(at(p0, axis0, angle0), at(p1, axis1, angle1));
    if (intersects(a, Pose::Identity(), b, motion.start())) continue;
    ContinuousOptions apart;
    apart.apart_at_start = true;
    const ContinuousResult tested = time_of_impact(a, kStill, b, motion), skipped = time_of_impact(a, kStill, b, motion, apart);
    ASSERT_EQ(tested.collides, skipped.collides) << i;
    EXPECT_EQ(tested.time_of_impact, skipped.time_of_impact) << i;
    EXPECT_EQ(tested.point_W, skipped.point_W) << i;
    ++compared;
    hits += tested.collides;
  }
  EXPECT_GT(compared, 20);
  EXPECT_GT(hits, 5);
}

}  // namespace
}  // namespace arphys::collision

namespace arphys::collision {
namespace {

Pose pose_from(double x, double y, double z, double qw, double qx, double qy, double qz) {
  Pose X = Pose::Identity();
  X.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(x, y, z);
  return X;
}

// A box settling on another in the drop1000 pile (t = 0.28 s, one 1 ms step, recorded):
// the lower one turns on the floor, the upper one tilts back by 3 mrad, 1 um apart.
// No contact, and cheaply: the edge/edge coplanarity of two edges lying in the contact
// plane is bounded along the motion (a first-order Taylor enclosure), not by boxes
// that the motion inflates in every direction. This query took 9,332 search nodes
// before (about 7 ms; a pile of them made a step take a second).
TEST(ContinuousQuery, BoxSettlingOnABoxIsCheapToClear) {
  const CollisionMesh cube(geometry::make_box_mesh(Eigen::Vector3d::Constant(0.2)));
  const ScrewMotion lower(
      pose_from(-1.2247776516061153, -1.5750494408950066, 0.10000100000000001, 0.99803026160878938, 0, 0,
                -0.062734335997851665),
      pose_from(-1.2247704953364869, -1.5750297831448123, 0.10000100000000001, 0.99802608996415254, 0, 0,
                -0.062800666802713664));
  const ScrewMotion upper(
      pose_from(-1.2252132504900402, -1.5748901868088825, 0.30165310608060592, 0.99806158761789576,
                0.008058127052901461, -0.0013915770824625407, 0.061694387291457209),
      pose_from(-1.2252172818412741, -1.5748797098473837, 0.30133101843610899, 0.99806878711424019,
                0.0064848110234681329, -0.001209550605369518, 0.061767146620453364));
  const ContinuousResult r = time_of_impact(cube, lower, cube, upper);
  EXPECT_FALSE(r.collides);
  EXPECT_LT(r.stats.search_nodes, 500) << r.stats.search_nodes;
}

// A box 1 um above another slides 1 mm across it, turning, and sinks 2 um on the way:
// it meets the lower box when the gap closes, half way.
TEST(ContinuousQuery, BoxSlidingDownOntoABoxMeetsItWhenTheGapCloses) {
  const CollisionMesh cube(geometry::make_box_mesh(Eigen::Vector3d::Constant(0.2)));
  const Pose start = at({0, 0, 0.200001}, Eigen::Vector3d::UnitZ(), 0.2);
  const Pose end = at({0.001, 0.0004, 0.199999}, Eigen::Vector3d::UnitZ(), 0.201);
  expect_toi(time_of_impact(cube, kStill, cube, ScrewMotion(start, end)), 0.5, 1e-6);
}

}  // namespace
}  // namespace arphys::collision

namespace arphys::collision {
namespace {

// A proxy held where times of impact stopped it (application 1's spoon at the teacup, while
// the tracked spoon goes on into it) meets at once: the query answers 0 after the first
// touching triangle pair, instead of going on to test every pair whose interval also starts
// at 0, none of which can be earlier. The held ball's query tested 273 pairs before.
TEST(ContinuousQuery, HeldProxyAnswersZeroAtTheFirstTouchingPair) {
  const CollisionMesh ball(geometry::make_sphere_mesh(0.1, 3));
  const CollisionMesh floor(slab());
  ContinuousOptions options;
  options.time_tolerance = 1e-6;  // (a simulation's)
  const Pose target = at({0.03, 0.01, 0.04}, Eigen::Vector3d::UnitX(), 0.3);
  Pose proxy = geometry::translation_pose({0, 0, 0.15});
  ContinuousResult r;
  for (int step = 0; step < 3; ++step) {  // the proxy stops at each time of impact
    const ScrewMotion towards(proxy, target);
    r = time_of_impact(floor, kStill, ball, towards, options);
    ASSERT_TRUE(r.collides) << step;
    proxy = towards.pose_at(r.time_of_impact);
  }
  EXPECT_EQ(r.time_of_impact, 0.0);
  EXPECT_LE(r.stats.triangle_pairs_tested, 8) << r.stats.triangle_pairs_tested;
}

}  // namespace
}  // namespace arphys::collision
