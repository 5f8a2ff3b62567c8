#include "simulator/geometry/screw_motion.hpp"

#include <gtest/gtest.h>

#include <random>

#include "tests/support/poses.hpp"

namespace arphys::geometry {
namespace {

using testing::random_pose;

double pose_error(const Pose& a, const Pose& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

TEST(ScrewMotion, EndpointsMatchTo1e12) {
  std::mt19937 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const Pose X0 = random_pose(rng, 2.0), X1 = random_pose(rng, 2.0);
    const ScrewMotion screw(X0, X1);
    EXPECT_LT(pose_error(screw.pose_at(0.0), X0), 1e-12);
    EXPECT_LT(pose_error(screw.pose_at(1.0), X1), 1e-12);
    // The displacement formula itself (not the exact endpoint shortcut) must land on X1 too.
    EXPECT_LT(pose_error(screw.displacement_at(1.0 - 1e-15) * X0, X1), 1e-12);
    EXPECT_LT(pose_error(screw.pose_at(1e-15), X0), 1e-12);
  }
}

// Every point of a body under a screw motion moves along a helix at constant speed,
// and the body turns at a constant rate: equal time steps give equal chord lengths
// and equal relative rotation angles.
TEST(ScrewMotion, SampledPathHasConstantAngularAndLinearSpeed) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose X0 = random_pose(rng, 1.0), X1 = random_pose(rng, 1.0);
    const ScrewMotion screw(X0, X1);
    const Eigen::Vector3d p_B(0.3, -0.2, 0.1);  // a point of the body, body frame
    constexpr int kSteps = 50;
    std::vector<double> chords, angles;
    for (int k = 0; k < kSteps; ++k) {
      const Pose a = screw.pose_at(double(k) / kSteps), b = screw.pose_at(double(k + 1) / kSteps);
      chords.push_back((b * p_B - a * p_B).norm());
      angles.push_back(rotation_distance_rad(a, b));
    }
    for (int k = 1; k < kSteps; ++k) {
      EXPECT_NEAR(chords[k], chords[0], 1e-12);
      EXPECT_NEAR(angles[k], angles[0], 1e-9);  // acos-based angle extraction limits this one
    }
    EXPECT_NEAR(angles[0] * kSteps, screw.angle_rad(), 1e-8);
  }
}

TEST(ScrewMotion, VelocityFieldMatchesFiniteDifference) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const ScrewMotion screw(random_pose(rng, 1.0), random_pose(rng, 1.0));
    const Eigen::Vector3d p_B(0.1, 0.4, -0.3);
    const double t = 0.37, h = 1e-6;
    const Eigen::Vector3d fd = (screw.pose_at(t + h) * p_B - screw.pose_at(t - h) * p_B) / (2 * h);
    EXPECT_LT((screw.velocity_of_point(screw.pose_at(t) * p_B) - fd).norm(), 1e-7);
  }
}

TEST(ScrewMotion, PureTranslationIsLinearInterpolation) {
  const Pose X0 = translation_pose({3, 0, 0}) * rotation_pose({0, 0, 1}, 0.4);
  const Pose X1 = translation_pose({-3, 1, 2}) * rotation_pose({0, 0, 1}, 0.4);
  const ScrewMotion screw(X0, X1);
  EXPECT_TRUE(screw.is_pure_translation());
  EXPECT_DOUBLE_EQ(screw.angle_rad(), 0.0);
  // FCL's ScrewMotion gets this case wrong (3 -> -3 ends at -33); ours is the straight line.
  const Pose mid = screw.pose_at(0.5);
  EXPECT_LT((mid.translation() - Eigen::Vector3d(0, 0.5, 1)).norm(), 1e-15);
  EXPECT_LT((mid.linear() - X0.linear()).norm(), 1e-15);
  EXPECT_LT((screw.velocity_of_point({5, 5, 5}) - Eigen::Vector3d(-6, 1, 2)).norm(), 1e-15);
}

TEST(ScrewMotion, TinyRotationIsContinuousWithTranslation) {
  const Pose X0 = translation_pose({1, 2, 3});
  for (double angle : {1e-3, 1e-6, 1e-9, 1e-12, 1e-15}) {
    const Pose X1 = translation_pose({2, 2, 3}) * rotation_pose({0, 1, 0}, angle);
    const ScrewMotion screw(X0, X1);
    EXPECT_NEAR(screw.angle_rad(), angle, 1e-15);
    const Pose mid = screw.pose_at(0.5);
    EXPECT_TRUE(mid.matrix().allFinite());
    EXPECT_NEAR(mid.translation().x(), 1.5, angle + 1e-14);
    EXPECT_LT(pose_error(screw.pose_at(1.0 - 1e-12), X1), 1e-11);
  }
}

TEST(ScrewMotion, RotationNearPiIsWellDefined) {
  for (double angle : {M_PI, M_PI - 1e-9, M_PI - 1e-4}) {
    const Pose X0 = translation_pose({0.2, 0, 0});
    const Pose X1 = translation_pose({0.5, 0.1, 0.4}) * rotation_pose({1, 1, 0}, angle);
    const ScrewMotion screw(X0, X1);
    EXPECT_NEAR(screw.angle_rad(), angle, 1e-9);
    EXPECT_LE(screw.angle_rad(), M_PI);
    EXPECT_LT(pose_error(screw.displacement_at(1.0 - 1e-15) * X0, X1), 1e-12);
    const Pose half = screw.pose_at(0.5);
    EXPECT_NEAR(rotation_distance_rad(X0, half), 0.5 * angle, 1e-9);
  }
}

TEST(ScrewMotion, PureRotationAboutOffsetAxisKeepsAxisPointsFixed) {
  // Rotate 90 degrees about the vertical axis through (1, 0, 0).
  const Pose about = translation_pose({1, 0, 0}) * rotation_pose({0, 0, 1}, M_PI / 2) * translation_pose({-1, 0, 0});
  const Pose X0 = translation_pose({2, 0, 0});
  const ScrewMotion screw(X0, about * X0);
  EXPECT_NEAR(screw.axial_displacement_m(), 0.0, 1e-15);
  for (double t : {0.1, 0.5, 0.9}) {
    // The body origin stays on the unit circle around the axis.
    const Eigen::Vector3d p = screw.pose_at(t).translation();
    EXPECT_NEAR((p - Eigen::Vector3d(1, 0, 0)).norm(), 1.0, 1e-14);
    EXPECT_NEAR(std::atan2(p.y(), p.x() - 1.0), t * M_PI / 2, 1e-14);
  }
}

// Two motions of a body from one start pose, as a re-solve changes a step's velocities: no
// point within the radius strays further from its place on the first than the bound, at
// any time of the step; and the bound is tight enough to be of use (within 3x of the worst
// sampled point, which with a turn as large as the shift needs the radius term).
TEST(ScrewMotion, MotionChangeBoundHoldsForEveryPointAllAlong) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-1, 1);
  constexpr double kRadius_m = 0.08;
  double loosest = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Pose X0 = random_pose(rng, 1.0);
    // A step of a body: up to 2 cm and 0.3 rad; the re-solve changes it by up to a tenth.
    const Pose step = testing::at(0.02 * Eigen::Vector3d(u(rng), u(rng), u(rng))) *
                      Pose(Eigen::AngleAxisd(0.3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
    const Pose change = testing::at(0.002 * Eigen::Vector3d(u(rng), u(rng), u(rng))) *
                        Pose(Eigen::AngleAxisd(0.03 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
    const Pose X1 = Pose(step.linear()) * X0;
    const ScrewMotion before(X0, testing::at(step.translation()) * X1);
    const ScrewMotion now(X0, testing::at(change.translation()) * Pose(change.linear()) * before.end());
    const double bound = motion_change_bound_m(before, now, kRadius_m);
    double worst = 0;
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector3d p_B = kRadius_m * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized() * std::abs(u(rng));
      for (int i = 0; i <= 20; ++i) {
        const double t = i / 20.0;
        worst = std::max(worst, (now.pose_at(t) * p_B - before.pose_at(t) * p_B).norm());
      }
    }
    EXPECT_LE(worst, bound * (1 + 1e-12)) << "trial " << trial;
    loosest = std::max(loosest, bound / worst);
  }
  EXPECT_LT(loosest, 3.0);
  EXPECT_EQ(motion_change_bound_m(ScrewMotion(Pose::Identity(), testing::at({0.01, 0, 0})),
                                  ScrewMotion(Pose::Identity(), testing::at({0.01, 0, 0})), kRadius_m),
            0.0);
}

}  // namespace
}  // namespace arphys::geometry
