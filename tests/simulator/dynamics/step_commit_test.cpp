// The last stage of a part (step_commit.hpp): bodies moved along their motions, never NaN.
#include "simulator/dynamics/step_commit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/simulator/dynamics/test_bodies.hpp"
#include "tests/support/thrown.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

TEST(StepCommit, BodiesEndTheFractionOfTheirScrewTheyTookAndANumericalFailureStaysAtRest) {
  std::vector<RigidBody> start = {plane_body(), cube("a", {0, 0, 1}), cube("b", {1, 0, 1})};
  start[2].v_WBcm_m_s = {3, 0, 0};
  testing::StageWorld world = testing::stage_world(start);
  const WorldModel& model = world.model;
  std::vector<BodyState>& bodies = world.state;
  const std::vector<int> participants{0, 1, 2};
  std::vector<BodyVelocity> u(3);
  u[1].v_WBcm_m_s = {0, 0, -2};
  u[2].v_WBcm_m_s = {NAN, 0, 0};
  // a turns a quarter about z while it drops 20 mm; half of that is taken.
  geometry::Pose turned = geometry::translation_pose({0, 0, 0.98});
  turned.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::vector<geometry::Pose> next = {bodies[0].X_WB, turned, geometry::translation_pose({1.1, 0, 1})};
  std::vector<Eigen::AlignedBox3d> swept(3);
  EXPECT_EQ(commit_motion(model, bodies, participants, u, next, 0.5, swept), 1);
  EXPECT_NEAR(bodies[1].X_WB.translation().z(), 0.99, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(bodies[1].X_WB.linear()).angle(), M_PI / 4, 1e-12);
  EXPECT_EQ(bodies[1].v_WBcm_m_s, u[1].v_WBcm_m_s);
  EXPECT_TRUE(swept[1].contains(bodies[1].X_WB.translation()));
  // b's motion was non-finite: where it was, at rest, and counted.
  EXPECT_EQ(bodies[2].X_WB.translation(), Eigen::Vector3d(1, 0, 1));
  EXPECT_TRUE(bodies[2].v_WBcm_m_s.isZero());
  EXPECT_TRUE(swept[0].isEmpty());  // the floor does not move
}

}  // namespace
}  // namespace arphys::dynamics

namespace arphys::dynamics {
namespace {

// A stage given inputs that do not fit its participants refuses them, naming the stage and
// the input, before it reads past the end of anything.
TEST(StepContracts, StagesRefuseInputsThatDoNotFitTheirParticipants) {
  const testing::StageWorld world = testing::stage_world({testing::plane_body(), testing::cube("a", {0, 0, 1})});
  const WorldModel& model = world.model;
  std::vector<BodyState> bodies = world.state;
  const auto message = arphys::testing::invalid_argument_message;
  std::vector<Eigen::AlignedBox3d> swept(2);
  EXPECT_EQ(message([&] {
              commit_motion(model, bodies, {0, 1}, std::vector<BodyVelocity>(1), {bodies[0].X_WB, bodies[1].X_WB}, 1.0,
                            swept);
            }),
            "commit_motion: u has 1 entries, expected 2");
  EXPECT_EQ(message([&] {
              candidate_poses(model, bodies, {1, 0}, std::vector<BodyVelocity>(2), 0.0, 0.01);
            }),
            "candidate_poses: participant 1 is body 0, expected increasing indices below 2");
  EXPECT_EQ(message([&] {
              candidate_poses(model, bodies, {0, 2}, std::vector<BodyVelocity>(2), 0.0, 0.01);
            }),
            "candidate_poses: participant 1 is body 2, expected increasing indices below 2");
  // A state for each of the model's bodies.
  const std::vector<BodyState> one_short(1);
  EXPECT_EQ(message([&] { candidate_poses(model, one_short, {0}, std::vector<BodyVelocity>(1), 0.0, 0.01); }),
            "candidate_poses: state has 1 entries, expected 2");
}

}  // namespace
}  // namespace arphys::dynamics
