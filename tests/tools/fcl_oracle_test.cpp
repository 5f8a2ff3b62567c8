// The mesh CCD against FCL, the peer used as an oracle: dense sampling of FCL's discrete
// intersection test along the same screw motions (never late, at most 1e-6 early, nothing
// missed), and FCL's conservative advancement as a second opinion. A test of
// simulator/collision that needs tools/ccd_bench's reference, so it lives here, apart from
// the library's own unit tests.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "tests/support/poses.hpp"
#include "tests/support/toi_checks.hpp"
#include "tools/ccd_bench/fcl_reference.hpp"

namespace arphys::collision {
namespace {

using testing::at;
using testing::kStill;
using testing::random_vector;
using geometry::Pose;
using geometry::ScrewMotion;

// Our answer against the dense-sampling truth: a true hit must be found, never late
// (after the first sample found intersecting) and at most 1e-6 before the last free
// sample; a hit the sampling stepped over must be a real touch. Returns 1 for a true hit.
int check_against_truth(const ContinuousResult& ours, const ccd_reference::ReferenceToi& truth, const CollisionMesh& a,
                        const ScrewMotion& ma, const CollisionMesh& b, const ScrewMotion& mb, int motion) {
  if (truth.hit) {
    EXPECT_TRUE(ours.collides) << "missed motion " << motion;
    EXPECT_LE(ours.time_of_impact, truth.toi) << "late on motion " << motion;
    EXPECT_LE(truth.toi_lo - ours.time_of_impact, 1e-6) << "early on motion " << motion;
    return 1;
  }
  if (ours.collides) {
    const double t = ours.time_of_impact;
    EXPECT_LT(separation(a, ma.pose_at(t), b, mb.pose_at(t), 1).distance_m, 1e-6) << "motion " << motion;
  }
  return 0;
}

TEST(FclOracle, TwoRotatingBodiesAgreeWithSampledTruth) {
  const geometry::TriangleMesh mesh_a = geometry::make_box_mesh({0.4, 0.1, 0.2});
  const geometry::TriangleMesh mesh_b = geometry::make_sphere_mesh(0.15, 1);
  const CollisionMesh a(mesh_a), b(mesh_b);
  const ccd_reference::FclMesh fa(mesh_a), fb(mesh_b);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int i = 0; i < 60; ++i) {
    // (Drawn in a fixed order: the order of a call's arguments is the compiler's.)
    const Eigen::Vector3d axis_a0 = random_vector(rng);
    const double angle_a0 = u(rng);
    const Eigen::Vector3d axis_a1 = random_vector(rng);
    const double angle_a1 = 3 * u(rng);
    const Eigen::Vector3d p_b0{u(rng), u(rng), u(rng)}, axis_b0 = random_vector(rng);
    const double angle_b0 = 3 * u(rng);
    const Eigen::Vector3d p_b1{u(rng), u(rng), u(rng)}, axis_b1 = random_vector(rng);
    const double angle_b1 = 3 * u(rng);
    const ScrewMotion ma(at({0, 0, 0}, axis_a0, angle_a0), at({0, 0, 0}, axis_a1, angle_a1));
    const ScrewMotion mb(at(p_b0, axis_b0, angle_b0), at(p_b1, axis_b1, angle_b1));
    if (intersects(a, ma.start(), b, mb.start())) continue;
    const auto ours = time_of_impact(a, ma, b, mb);
    hits += check_against_truth(ours, ccd_reference::sampled_truth(fa, ma, fb, mb, 2000), a, ma, b, mb, i);
  }
  EXPECT_GE(hits, 3);
}

// The randomised oracle of the issue on the bunny: zero misses, zero late TOIs,
// |error| <= 1e-6 against the dense-sampling truth built on FCL's discrete test.
TEST(FclOracle, BunnyAgainstBunnyMatchesDenseSamplingTruth) {
  auto mesh = geometry::load_mesh(std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-5k.obj");
  const double diagonal = mesh.bounds().diagonal().norm();
  const Eigen::Vector3d centre = mesh.bounds().center();
  for (auto& v : mesh.vertices_m) v = (v - centre) / diagonal;
  const CollisionMesh bunny(mesh);
  const ccd_reference::FclMesh fcl_bunny(mesh);
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(-0.9, 0.9), angle(0, M_PI / 2);
  int hits = 0, grazing = 0, tested = 0, fcl_compared = 0;
  while (tested < 60) {
    Pose X0 = Pose::Identity(), X1 = Pose::Identity();
    // Rotations and axes from this test's generator (Eigen's Random draws on std::rand,
    // which other tests in the binary draw on too: the cases would depend on test order).
    std::normal_distribution<double> normal;
    // (Each draw its own statement: the order of a call's arguments is the compiler's.)
    const double qw = normal(rng), qx = normal(rng), qy = normal(rng), qz = normal(rng);
    X0.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
    const double ax = normal(rng), ay = normal(rng), az = normal(rng), turn = angle(rng);
    X1.linear() = Eigen::AngleAxisd(turn, Eigen::Vector3d(ax, ay, az).normalized()) * X0.linear();
    const double x0 = u(rng), y0 = u(rng), z0 = u(rng), x1 = u(rng), y1 = u(rng), z1 = u(rng);
    X0.translation() = Eigen::Vector3d(x0, y0, z0);
    X1.translation() = Eigen::Vector3d(x1, y1, z1);
    if (intersects(bunny, Pose::Identity(), bunny, X0) || intersects(bunny, Pose::Identity(), bunny, X1)) continue;
    ++tested;
    const ScrewMotion motion(X0, X1);
    const auto ours = time_of_impact(bunny, kStill, bunny, motion);
    const auto truth = ccd_reference::sampled_truth(fcl_bunny, kStill, fcl_bunny, motion, 1000);
    hits += check_against_truth(ours, truth, bunny, kStill, bunny, motion, tested);
    grazing += !truth.hit && ours.collides;
    if (truth.hit) {
      // Second opinion: FCL's conservative advancement on RSS (its only miss-free CCD
      // here, late by up to ~1e-4 in the anchor runs).
      if (fcl_compared < 8) {
        ++fcl_compared;
        const auto fcl = ccd_reference::fcl_conservative_advancement(fcl_bunny, kStill, fcl_bunny, motion,
                                                                     ccd_reference::FclBoundingVolume::kRss);
        EXPECT_TRUE(fcl.hit) << "motion " << tested;
        EXPECT_NEAR(fcl.toi, ours.time_of_impact, 3e-4) << "motion " << tested;
      }
    }
  }
  EXPECT_GT(hits, 12);
  EXPECT_EQ(fcl_compared, 8);
  EXPECT_LE(grazing, 3);
}

}  // namespace
}  // namespace arphys::collision
