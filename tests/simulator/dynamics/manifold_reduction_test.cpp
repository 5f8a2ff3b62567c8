// The contact points a body pair keeps when its manifold is larger than the limit.
#include "simulator/dynamics/manifold_reduction.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace arphys::dynamics {
namespace {

collision::ManifoldPoint point_at(const Eigen::Vector3d& p_W, const Eigen::Vector3d& normal_W, double distance_m) {
  return {p_W, p_W + distance_m * normal_W, normal_W, distance_m, {}};
}

// A patch of 5 x 5 points 0.5 mm apart along `normal_W`, spread 4 cm across it.
void add_patch(std::vector<collision::ManifoldPoint>& points, const Eigen::Vector3d& normal_W, const Eigen::Vector3d& at_W) {
  const Eigen::Vector3d t1 = normal_W.unitOrthogonal(), t2 = normal_W.cross(t1);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) points.push_back(point_at(at_W + 0.01 * (i - 2) * t1 + 0.01 * (j - 2) * t2, normal_W, 5e-4));
}

TEST(ManifoldReduction, SmallManifoldsAreKeptWhole) {
  std::vector<collision::ManifoldPoint> points;
  for (int k = 0; k < 16; ++k) points.push_back(point_at(Eigen::Vector3d(k, 0, 0), Eigen::Vector3d::UnitZ(), 1e-4 * k));
  EXPECT_EQ(reduce_manifold(points, 16).size(), 16u);
}

// Two bunnies within the contact tolerance: large patches a millimetre apart in three
// directions, and one edge pair in a fourth that touches. The touching pair is kept
// (taking the largest patches' extremes first filled the limit and dropped it), and
// so is each patch's closest point.
TEST(ManifoldReduction, TheTouchingFeatureIsKeptBeforeTheExtremesOfLargerPatches) {
  std::vector<collision::ManifoldPoint> points;
  add_patch(points, Eigen::Vector3d::UnitZ(), {0, 0, 0});
  add_patch(points, Eigen::Vector3d::UnitY(), {0, 0.1, 0});
  add_patch(points, -Eigen::Vector3d::UnitY(), {0, -0.1, 0});
  points[30].distance_m = 2e-4;  // the +y patch's closest point
  const Eigen::Vector3d touching_normal = Eigen::Vector3d(1, 0, 1).normalized();
  points.push_back(point_at({0.05, 0, 0.05}, touching_normal, 2e-12));
  const auto kept = reduce_manifold(points, 16);
  ASSERT_LE(kept.size(), 16u);
  ASSERT_FALSE(kept.empty());
  EXPECT_EQ(kept.front().distance_m, 2e-12);  // nearest first
  EXPECT_TRUE(kept.front().normal_W.isApprox(touching_normal));
  EXPECT_EQ(std::count_if(kept.begin(), kept.end(), [](const auto& p) { return p.distance_m == 2e-4; }), 1);
  // Every direction is represented.
  for (const Eigen::Vector3d& n : {Eigen::Vector3d(Eigen::Vector3d::UnitZ()), Eigen::Vector3d(Eigen::Vector3d::UnitY()),
                                   Eigen::Vector3d(-Eigen::Vector3d::UnitY())})
    EXPECT_TRUE(std::any_of(kept.begin(), kept.end(), [&](const auto& p) { return p.normal_W.isApprox(n); }));
}

// A box face on a table, as a mesh: 25 vertices on one normal. The four corners of the
// patch (its support polygon) are kept.
TEST(ManifoldReduction, OnePatchKeepsItsCorners) {
  std::vector<collision::ManifoldPoint> points;
  add_patch(points, Eigen::Vector3d::UnitZ(), {0, 0, 0});
  const auto kept = reduce_manifold(points, 8);
  ASSERT_LE(kept.size(), 8u);
  for (const double x : {-0.02, 0.02})
    for (const double y : {-0.02, 0.02})
      EXPECT_TRUE(std::any_of(kept.begin(), kept.end(), [&](const auto& p) {
        return std::abs(std::abs(p.point_A_W.x()) - 0.02) < 1e-12 && std::abs(std::abs(p.point_A_W.y()) - 0.02) < 1e-12 &&
               p.point_A_W.x() * x > 0 && p.point_A_W.y() * y > 0;
      })) << "corner " << x << ", " << y;
}

}  // namespace
}  // namespace arphys::dynamics
