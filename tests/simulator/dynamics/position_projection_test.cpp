// Post-stabilisation of deep points (simulator/dynamics/position_projection.hpp).
#include "simulator/dynamics/position_projection.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace arphys::dynamics {
namespace {

// A 1 kg, 0.2 m cube's inverse inertia (I = m a^2 / 6 about its centre).
Eigen::Matrix3d cube_inverse_inertia(double mass_kg) { return Eigen::Matrix3d::Identity() / (mass_kg * 0.04 / 6); }

ProjectedBody dynamic_cube(double mass_kg, const Eigen::Vector3d& center_W) {
  ProjectedBody body;
  body.X_WB = geometry::Pose::Identity();
  body.X_WB.translation() = center_W;
  body.inverse_mass_1_kg = 1 / mass_kg;
  body.inverse_inertia_W = cube_inverse_inertia(mass_kg);
  return body;
}

ProjectedBody fixed_floor() {
  ProjectedBody floor;
  floor.X_WB = geometry::Pose::Identity();
  return floor;
}

// A point of the body b held on the floor's top (z = 0, normal +z): b's material point
// at p_B, 5 um below the floor where the floor's point is.
ProjectedPoint on_floor(int b, const Eigen::Vector3d& p_W, const std::vector<ProjectedBody>& bodies, double target_m) {
  ProjectedPoint point;
  point.body_a = 0;
  point.body_b = b;
  point.point_A_B = Eigen::Vector3d(p_W.x(), p_W.y(), 0);
  point.point_B_B = bodies[b].X_WB.inverse() * p_W;
  point.normal_A_B = Eigen::Vector3d::UnitZ();
  point.target_depth_m = target_m;
  return point;
}

TEST(PositionProjection, APointUnderTheCentreLiftsTheBodyStraightUpByItsDepth) {
  std::vector<ProjectedBody> bodies{fixed_floor(), dynamic_cube(1.0, {0, 0, 0.1 - 5e-6})};
  const std::vector<ProjectedPoint> points{on_floor(1, {0, 0, -5e-6}, bodies, -1e-6)};
  EXPECT_NEAR(projected_depth_m(bodies, points[0]), 5e-6, 1e-15);
  const ProjectionResult result = project_points(bodies, points, 1e-9, 10);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.sweeps, 1);  // exact in one lift: no lever arm
  EXPECT_NEAR(bodies[1].X_WB.translation().z(), 0.1 + 1e-6, 1e-15);  // to the 1 um gap
  EXPECT_TRUE(bodies[1].X_WB.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  EXPECT_EQ(bodies[0].X_WB.translation(), Eigen::Vector3d::Zero());  // the floor does not move
}

TEST(PositionProjection, TwoBodiesShareTheLiftByTheirInverseMasses) {
  // Box b (3 kg) 6 um into box a (1 kg) along x, on the line of both centres.
  std::vector<ProjectedBody> bodies{dynamic_cube(1.0, {0, 0, 0}), dynamic_cube(3.0, {0.2 - 6e-6, 0, 0})};
  ProjectedPoint point;
  point.body_a = 0;
  point.body_b = 1;
  point.point_A_B = {0.1, 0, 0};
  point.point_B_B = {-0.1, 0, 0};
  point.normal_A_B = Eigen::Vector3d::UnitX();
  point.target_depth_m = 0;
  ASSERT_NEAR(projected_depth_m(bodies, point), 6e-6, 1e-15);
  ASSERT_TRUE(project_points(bodies, {point}, 1e-12, 10).converged);
  // The smallest move in the mass metric: a (1 kg) takes 3/4 of the 6 um, b (3 kg) 1/4.
  EXPECT_NEAR(bodies[0].X_WB.translation().x(), -4.5e-6, 1e-15);
  EXPECT_NEAR(bodies[1].X_WB.translation().x(), 0.2 - 6e-6 + 1.5e-6, 1e-15);
  EXPECT_NEAR(projected_depth_m(bodies, point), 0, 1e-15);
}

TEST(PositionProjection, ACornerLiftsByTurningAndRisingWithinItsTolerance) {
  // A corner 8 um deep, 0.1 m off the centre in x and y: the lift turns the cube too
  // (its corner's effective mass is under its mass), and converges in a few sweeps as
  // the turn's second-order term shrinks.
  std::vector<ProjectedBody> bodies{fixed_floor(), dynamic_cube(1.0, {0, 0, 0.1 - 8e-6})};
  const std::vector<ProjectedPoint> points{on_floor(1, {0.1, 0.1, -8e-6}, bodies, -1e-6)};
  const ProjectionResult result = project_points(bodies, points, 1e-10, 20);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(projected_depth_m(bodies, points[0]), -1e-6 + 1e-10);
  // w = 1/m + |r x n|^2 / I = 1 + 0.02 / (0.04 / 6) = 4: the centre rises a quarter of the 9 um.
  EXPECT_NEAR(bodies[1].X_WB.translation().z() - (0.1 - 8e-6), 9e-6 / 4, 1e-9);
  const double turn_rad = Eigen::AngleAxisd(bodies[1].X_WB.linear()).angle();
  EXPECT_NEAR(turn_rad, 9e-6 * 0.75 / std::hypot(0.1, 0.1), 1e-9);  // the rest of the lift by turning
}

TEST(PositionProjection, APointBetweenTwoFixedBodiesIsReportedAndMovesNothing) {
  std::vector<ProjectedBody> bodies{fixed_floor(), fixed_floor()};
  bodies[1].X_WB.translation() = Eigen::Vector3d(0, 0, -3e-6);
  const std::vector<ProjectedPoint> points{on_floor(1, {0, 0, -3e-6}, bodies, 0.0)};
  const ProjectionResult result = project_points(bodies, points, 1e-9, 5);
  EXPECT_FALSE(result.converged);
  EXPECT_NEAR(result.worst_excess_m, 3e-6, 1e-15);
  EXPECT_EQ(bodies[1].X_WB.translation(), Eigen::Vector3d(0, 0, -3e-6));
}

TEST(PositionProjection, ANonPositiveToleranceIsRefusedByValue) {
  std::vector<ProjectedBody> bodies{fixed_floor()};
  try {
    project_points(bodies, {}, 0.0, 5);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tolerance_m must be positive, got 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arphys::dynamics
