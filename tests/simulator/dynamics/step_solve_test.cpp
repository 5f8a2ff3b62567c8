// The solve stage of a step (step_solve.hpp): rows from contacts, the solve, the launch guard.
#include "simulator/dynamics/step_solve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "simulator/collision/shape_query.hpp"
#include "tests/simulator/dynamics/test_bodies.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

// A 1 kg, 0.2 m cube `gap_m` above the floor (body 0), moving at v_z_m_s, and its contacts.
struct CubeOnFloor {
  WorldModel model;
  std::vector<BodyState> bodies;
  std::vector<Contact> contacts;
  std::vector<int> participants{0, 1};
};
CubeOnFloor cube_on_floor(double gap_m, double v_z_m_s, double restitution = 0) {
  CubeOnFloor scene;
  std::vector<RigidBody> bodies = {plane_body(), cube("cube", {0, 0, 0.1 + gap_m})};
  bodies[1].v_WBcm_m_s.z() = v_z_m_s;
  bodies[1].restitution = restitution;
  for (const auto& feature :
       collision::contact_manifold(bodies[0].shape, bodies[0].X_WB, bodies[1].shape, bodies[1].X_WB, 1e-3))
    scene.contacts.push_back({0, 1, feature});
  testing::StageWorld world = testing::stage_world(bodies);
  scene.model = std::move(world.model);
  scene.bodies = std::move(world.state);
  return scene;
}

TEST(StepSolve, ARowClosesAtMostToTheRestingGapWithinTheStep) {
  const CubeOnFloor scene = cube_on_floor(0.5e-3, 0);
  ASSERT_EQ(scene.contacts.size(), 4u);
  const SolveSetup setup = prepare_solve(scene.model, scene.bodies, 0.01, 0.01, scene.participants, scene.contacts);
  // 0.5 mm less the 1 um gap over 10 ms: the row lets the cube approach at 0.0499 m/s.
  EXPECT_NEAR(setup.resting_rows[0].min_normal_velocity_m_s, -(0.5e-3 - 1e-6) / 0.01, 1e-12);
  EXPECT_EQ(setup.resting_rows[0].body_a, -1);  // the floor is not an unknown
  EXPECT_EQ(setup.resting_rows[0].body_b, 0);
  // Gravity over the step in the unconstrained velocity.
  EXPECT_NEAR(setup.u_unconstrained[0].v_WBcm_m_s.z(), -0.0981, 1e-12);
}

TEST(StepSolve, AnApproachThatMeetsWithinTheStepBouncesWithTheRestitution) {
  // 1 m/s down from 0.5 mm: it meets within 10 ms, and leaves at half the speed.
  const CubeOnFloor scene = cube_on_floor(0.5e-3, -1.0, 0.5);
  const SolveSetup setup = prepare_solve(scene.model, scene.bodies, 0.01, 0.01, scene.participants, scene.contacts);
  EXPECT_NEAR(setup.resting_rows[0].min_normal_velocity_m_s, 0.5, 1e-12);
  // 20 mm above (a contact row the tolerance would not give, built here), 1 m/s does not
  // meet within the step: no bounce yet, the gap bounds the approach.
  const CubeOnFloor far = cube_on_floor(20e-3, -1.0, 0.5);
  Contact row_20mm = scene.contacts[0];
  row_20mm.feature.point_B_W.z() += 20e-3 - 0.5e-3;
  row_20mm.feature.distance_m = 20e-3;
  const SolveSetup far_setup = prepare_solve(far.model, far.bodies, 0.01, 0.01, far.participants, {});
  EXPECT_NEAR(contact_row(far.model, far.bodies, row_20mm, far_setup, far.participants).min_normal_velocity_m_s,
              -(20e-3 - 1e-6) / 0.01, 1e-12);
}

TEST(StepSolve, ARestingCubeIsHeldWithItsWeightOverTheStep) {
  const CubeOnFloor scene = cube_on_floor(1e-6, 0);
  const SolveSetup setup = prepare_solve(scene.model, scene.bodies, 0.01, 0.01, scene.participants, scene.contacts);
  const StepSolve solved =
      solve_step(scene.model, scene.bodies, setup, scene.participants, scene.contacts, {}, nullptr);
  ASSERT_EQ(solved.u.size(), 2u);
  EXPECT_NEAR(solved.u[1].v_WBcm_m_s.z(), 0, 1e-9);
  double impulse_N_s = 0;
  for (const Contact& c : solved.solved) impulse_N_s += c.impulse_N_s;
  EXPECT_NEAR(impulse_N_s, 0.0981, 1e-9);  // m g h
  EXPECT_EQ(solved.launches_prevented, 0);
  EXPECT_FALSE(solved.infeasible);
}

TEST(StepSolve, AMeetingTheSweepFoundIsARowOfTheSolve) {
  // No resting contact; the CCD's meeting under the cube's bottom face centre, 20 mm down,
  // reached within the step at 3 m/s.
  CubeOnFloor scene = cube_on_floor(0.02, -3.0, 0.5);
  ImpactPoint hit;
  hit.point_A_B = {0, 0, 0};
  hit.point_B_B = {0, 0, -0.1};
  hit.normal_A_B = {0, 0, 1};
  const ImpactMap impacts{{{0, 1}, {hit}}};
  const SolveSetup setup = prepare_solve(scene.model, scene.bodies, 0.01, 0.01, scene.participants, {});
  const StepSolve solved = solve_step(scene.model, scene.bodies, setup, scene.participants, {}, impacts, nullptr);
  ASSERT_EQ(solved.solved.size(), 1u);
  EXPECT_NEAR(solved.solved[0].feature.distance_m, 0.02, 1e-12);
  // It bounces at the step's boundary with half its approach speed.
  EXPECT_NEAR(solved.u[1].v_WBcm_m_s.z(), 1.5, 1e-9);
  EXPECT_GT(solved.solved[0].impulse_N_s, 4.5);  // 1 kg from -3 m/s to 1.5 m/s
}

TEST(StepSolve, TheLaunchGuardSlowsABodyASolveLeftFarTooFast) {
  const CubeOnFloor scene = cube_on_floor(1e-6, 0);
  const SolveSetup setup = prepare_solve(scene.model, scene.bodies, 0.01, 0.01, scene.participants, scene.contacts);
  std::vector<BodyVelocity> u = setup.u_unconstrained;
  u[0].v_WBcm_m_s = {100, 0, 0};  // what a failed solve might leave
  EXPECT_EQ(guard_launches(scene.model, scene.bodies, setup, scene.participants, setup.resting_rows, u), 1);
  // Twice the fastest motion it couples (the fall's 0.0981 m/s), the depenetration speed
  // and the slack.
  EXPECT_NEAR(u[0].v_WBcm_m_s.norm(), 2 * 0.0981 + 0.05 + 0.5, 1e-9);
  u[0].v_WBcm_m_s = {0, 0, NAN};
  EXPECT_EQ(guard_launches(scene.model, scene.bodies, setup, scene.participants, setup.resting_rows, u), 1);
  EXPECT_EQ(u[0].v_WBcm_m_s, setup.u_unconstrained[0].v_WBcm_m_s);
  EXPECT_EQ(guard_launches(scene.model, scene.bodies, setup, scene.participants, setup.resting_rows, u), 0);
}

}  // namespace
}  // namespace arphys::dynamics
