#include "simulator/collision/screw_enclosure.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tests/support/poses.hpp"

namespace arphys::collision {
namespace {

using testing::random_pose;

bool contains(const IVec3& box, const Eigen::Vector3d& p) {
  for (int i = 0; i < 3; ++i)
    if (!(box[i].lo <= p[i] && p[i] <= box[i].hi)) return false;
  return true;
}

// Positions of B's points in A's frame, sampled along both bodies' screws, must lie in
// both enclosures (natural interval extension and centered ball) of every sub-interval.
TEST(RelativeMotion, EnclosuresContainSampledPositionsAndRotations) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  int checked = 0;
  for (int m = 0; m < 200; ++m) {
    const bool a_moves = m % 2 == 0;
    const geometry::Pose XA0 = random_pose(rng, 1.0), XB0 = random_pose(rng, 1.0);
    const geometry::ScrewMotion motion_A(XA0, a_moves ? random_pose(rng, 1.0) : XA0);
    const geometry::ScrewMotion motion_B(XB0, random_pose(rng, 1.0));
    const RelativeMotion rel(motion_A, motion_B);
    // (From this test's generator: Eigen's Random draws on std::rand, shared with the
    // binary's other tests.)
    std::uniform_real_distribution<double> coordinate(-1, 1);
    const double x = coordinate(rng), y = coordinate(rng), z = coordinate(rng);
    const Eigen::Vector3d p_B(x, y, z);
    double t0 = u(rng), t1 = u(rng);
    if (t0 > t1) std::swap(t0, t1);
    const Interval T{t0, t1};
    const IVec3 natural = rel.point_over(p_B, T);
    const IVec3 ball = rel.point_ball(p_B, T).to_interval();
    const IMat3 R_ball = rel.rotation_ball(T).to_interval();
    for (int k = 0; k <= 20; ++k) {
      const double t = t0 + (t1 - t0) * k / 20.0;
      // Reference: the two poses composed directly (geometry's screw, not the enclosure's).
      const geometry::Pose X_AB = motion_A.pose_at(t).inverse() * motion_B.pose_at(t);
      const Eigen::Vector3d p = X_AB * p_B;
      ASSERT_TRUE(contains(natural, p)) << "motion " << m << " t " << t;
      ASSERT_TRUE(contains(ball, p)) << "motion " << m << " t " << t;
      EXPECT_NEAR((rel.point_at(p_B, t) - p).norm(), 0.0, 1e-12);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) ASSERT_TRUE(R_ball.m[i][j].contains(X_AB.linear()(i, j)));
      ++checked;
    }
  }
  EXPECT_EQ(checked, 200 * 21);
}

TEST(RelativeMotion, BallShrinksLinearlyWithTheInterval) {
  const geometry::Pose X0 = geometry::Pose::Identity();
  geometry::Pose X1 = geometry::rotation_pose(Eigen::Vector3d::UnitZ(), 1.0);
  X1.translation() = Eigen::Vector3d(1, 0, 0);
  const RelativeMotion rel(geometry::ScrewMotion(X0, X0), geometry::ScrewMotion(X0, X1));
  const double r1 = rel.point_ball(Eigen::Vector3d(1, 0, 0), {0.5, 0.5 + 1e-3}).rad.maxCoeff();
  const double r2 = rel.point_ball(Eigen::Vector3d(1, 0, 0), {0.5, 0.5 + 1e-6}).rad.maxCoeff();
  EXPECT_NEAR(r1 / r2, 1000.0, 1.0);
}

}  // namespace
}  // namespace arphys::collision
