// The rounds of a part of a step (step_rounds.hpp): a meeting the sweep finds is re-solved.
#include "simulator/dynamics/step_rounds.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "simulator/dynamics/step_commit.hpp"
#include "tests/simulator/dynamics/test_bodies.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

TEST(StepRounds, ABallMeetingTheFloorInsideTheStepBouncesInOneRound) {
  // A 1 kg ball 20 mm above the floor at 3 m/s down, restitution 0.5: it meets 2/3 into a
  // 10 ms step.
  RigidBody ball = cube("ball", {0, 0, 0.12});
  ball.shape = collision::Shape::sphere(0.1);
  ball.mass = geometry::with_mass(geometry::sphere_mass_properties(0.1, 1000), 1.0);
  std::vector<RigidBody> bodies = {plane_body(), ball};
  bodies[1].v_WBcm_m_s = {0, 0, -3};
  bodies[1].restitution = 0.5;
  const testing::StageWorld w = testing::stage_world(bodies);
  const std::vector<int> participants{0, 1};
  MeshCrossingMemo memo;
  memo.placed_since_step = {0, 0};
  const WorkerPool pool(1);
  std::vector<ContactHints::Bounce> held_back;
  const RoundsWorld world{{w.model, w.state, memo, pool}, 0.0, held_back};
  const std::vector<Contact> resting;  // nothing within the contact tolerance at the start
  SolvedIslands islands;
  PartSolve part{0.0, 0.01, 0.01, resting, {}, islands, std::nullopt};
  part.setup = prepare_solve(w.model, w.state, 0.01, 0.01, participants, resting);
  StepSolve first = solve_step(w.model, w.state, *part.setup, participants, resting, {}, &islands);
  PartMotion motion;
  motion.u = first.u;
  motion.next = candidate_poses(w.model, w.state, participants, motion.u, 0.0, 0.01);
  ImpactCache cache;
  std::vector<Contact> contacts;
  StepReport report;
  resolve_rounds(world, participants, part, cache, false, motion, contacts, report);
  EXPECT_EQ(report.impacts_resolved, 1);
  EXPECT_EQ(motion.tau, 1.0);  // nothing meets in the re-solved motion: no cut
  // Half the approach speed at the step's start, where the bounce happens.
  EXPECT_NEAR(motion.u[1].v_WBcm_m_s.z(), 1.5, 1e-9);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR(contacts[0].impulse_N_s, 1.5 + 3.0981, 1e-9);  // gravity's 0.0981 over the step undone too
  EXPECT_TRUE(held_back.empty());
}

}  // namespace
}  // namespace arphys::dynamics
