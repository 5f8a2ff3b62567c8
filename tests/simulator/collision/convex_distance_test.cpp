// GJK distances of convex pieces and the advancement built on them: the lower bound never
// exceeds the true distance (the hulls' exact triangle distance) and converges to it;
// sliding neighbours are proven apart without a sweep, a fall is timed exactly.
#include <gtest/gtest.h>

#include <random>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_distance.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/shape_query.hpp"
#include "tests/support/poses.hpp"

namespace arphys::collision {
namespace {

using geometry::Pose;
using testing::at;
using testing::random_pose;

TEST(ConvexDistance, BoundsAndConvergesToTheHullsDistance) {
  const auto set = load_convex_set(std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-1k-quadric.pieces.obj",
                                   Eigen::Vector3d::Constant(0.8));
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(set->pieces.size()) - 1);
  int apart = 0, overlapping = 0, iterations = 0;
#ifdef ARPHYS_UNDER_SANITIZERS
  const int trials = 400;  // memory and UB checks of the same paths (2000 take 25 s there)
#else
  const int trials = 2000;
#endif
  for (int trial = 0; trial < trials; ++trial) {
    const ConvexPiece& a = set->pieces[pick(rng)];
    const ConvexPiece& b = set->pieces[pick(rng)];
    const Pose X_WA = random_pose(rng, 0.0) * at(-a.centroid_m());
    const Pose X_WB = random_pose(rng, 0.06) * at(-b.centroid_m());
    const CollisionMesh mesh_a(a.hull()), mesh_b(b.hull());
    const bool crossing = intersects(mesh_a, X_WA, mesh_b, X_WB);
    const double truth = crossing ? 0.0 : separation(mesh_a, X_WA, mesh_b, X_WB).distance_m;
    const ConvexDistance d = convex_distance(a, X_WA, b, X_WB);
    EXPECT_LE(d.lower_m, truth + 1e-12) << "trial " << trial;
    if (crossing) {
      ++overlapping;
      EXPECT_LE(d.lower_m, 0) << "trial " << trial;
      continue;
    }
    // Apart, or one inside the other (no surfaces crossing): GJK measures the solids.
    if (d.upper_m == 0) continue;
    ++apart;
    EXPECT_NEAR(d.lower_m, truth, 1e-8) << "trial " << trial;
    EXPECT_NEAR(d.upper_m, truth, 1e-8) << "trial " << trial;
    iterations += d.iterations;
  }
  EXPECT_GT(apart, trials / 4);
  EXPECT_GT(overlapping, trials / 10);
  std::printf("GJK: %d apart (mean %.1f iterations), %d overlapping\n", apart, static_cast<double>(iterations) / apart,
              overlapping);
}

// Asked only whether they are further apart than a margin, it stops as soon as it knows.
TEST(ConvexDistance, StopsOnceTheMarginIsProven) {
  const ConvexPiece cube(geometry::make_box_mesh({0.1, 0.1, 0.1}));
  const ConvexDistance d = convex_distance(cube, Pose::Identity(), cube, at({0.3, 0.01, 0.02}), 0.05);
  EXPECT_GT(d.lower_m, 0.05);
  EXPECT_LE(d.lower_m, 0.2 + 1e-12);
  EXPECT_LE(d.iterations, 2);
  const auto set = make_convex_set({cube});
  EXPECT_TRUE(convex_sets_apart_by(*set, Pose::Identity(), *set, at({0.3, 0, 0}), 0.19));
  EXPECT_FALSE(convex_sets_apart_by(*set, Pose::Identity(), *set, at({0.3, 0, 0}), 0.21));
}

}  // namespace
}  // namespace arphys::collision

namespace arphys::collision {
namespace {

using geometry::Pose;
using geometry::ScrewMotion;
using testing::at;

std::shared_ptr<const ConvexSet> cube_set(double side_m) {
  std::vector<ConvexPiece> pieces;
  pieces.emplace_back(geometry::make_box_mesh(Eigen::Vector3d::Constant(side_m)));
  return make_convex_set(std::move(pieces));
}

// Two cubes 5 mm apart, one sliding 3 cm past the other and turning: proven apart by
// advancement alone, no triangle pair swept.
TEST(ConvexAdvancement, ProvesSlidingNeighboursApartWithoutASweep) {
  const Shape cube = Shape::convex_set(cube_set(0.1));
  const ScrewMotion still(Pose::Identity(), Pose::Identity());
  const ScrewMotion slide(at({0.105, 0, 0}), at({0.105, 0.03, 0}, Eigen::Vector3d::UnitZ(), 0.02));
  const ContinuousResult r = time_of_impact(cube, still, cube, slide);
  EXPECT_FALSE(r.collides);
  EXPECT_EQ(r.stats.triangle_pairs_tested, 0);
}

// A cube dropped 1 cm onto another: the advancement closes in, the sweep times the touch.
TEST(ConvexAdvancement, TimesAFallOntoAFace) {
  const Shape cube = Shape::convex_set(cube_set(0.1));
  const ScrewMotion still(Pose::Identity(), Pose::Identity());
  const ScrewMotion fall(at({0.01, 0.02, 0.11}), at({0.01, 0.02, 0.09}));
  ContinuousOptions options;
  options.time_tolerance = 1e-9;
  const ContinuousResult r = time_of_impact(cube, still, cube, fall, options);
  ASSERT_TRUE(r.collides);
  EXPECT_LE(r.time_of_impact, 0.5 + 1e-12);
  EXPECT_GE(r.time_of_impact, 0.5 - 2e-9);
  EXPECT_NEAR(r.normal_W.z(), 1, 1e-9);
}

}  // namespace
}  // namespace arphys::collision
