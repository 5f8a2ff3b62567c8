// The sweep stage of a step (step_sweep.hpp): CCD of moving pairs, end checks of resting ones.
#include "simulator/dynamics/step_sweep.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "tests/simulator/dynamics/test_bodies.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

// The floor and a 0.2 m cube `height_m` above it, swept to `drop_m` lower.
struct Drop {
  WorldModel model;
  std::vector<BodyState> bodies;
  std::vector<int> participants{0, 1};
  std::vector<geometry::Pose> next;
  MeshCrossingMemo memo;
  WorkerPool pool{1};
  SweepWorld world() { return {model, bodies, memo, pool}; }
};
Drop drop(double height_m, double drop_m) {
  Drop d;
  testing::StageWorld world = testing::stage_world({plane_body(), cube("cube", {0, 0, 0.1 + height_m})});
  d.model = std::move(world.model);
  d.bodies = std::move(world.state);
  d.next = {d.bodies[0].X_WB, geometry::translation_pose({0, 0, 0.1 + height_m - drop_m})};
  d.memo.placed_since_step = {0, 0};
  return d;
}

TEST(StepSweep, AFallingCubeMeetsTheFloorAtItsTimeOfImpactNeverLater) {
  Drop d = drop(0.02, 0.03);  // meets after 2/3 of the motion
  ImpactCache cache;
  ImpactMap meeting;
  const Sweep sweep = sweep_motions(d.world(), d.participants, d.next, nullptr, &cache, &meeting);
  EXPECT_EQ(sweep.ccd_queries, 1);
  EXPECT_FALSE(sweep.deepening);
  EXPECT_LE(sweep.tau, 2.0 / 3.0);
  EXPECT_GT(sweep.tau, 2.0 / 3.0 - 1e-6);
  ASSERT_EQ(meeting.count({0, 1}), 1u);
  // The meeting point on the cube's bottom face, with the floor's normal.
  const ImpactPoint& hit = meeting.at({0, 1}).front();
  EXPECT_NEAR(hit.point_B_B.z(), -0.1, 1e-6);
  EXPECT_NEAR(hit.normal_A_B.z(), 1.0, 1e-9);
  // Asked again for the same motion, the cache answers: no new query, the same time.
  const Sweep again = sweep_motions(d.world(), d.participants, d.next, nullptr, &cache, nullptr);
  EXPECT_EQ(again.ccd_queries, 0);
  EXPECT_EQ(again.tau, sweep.tau);
}

TEST(StepSweep, ARestingPairIsCheckedAtTheEndOfItsMotionNotSwept) {
  // Resting 1 um above the floor, moved 0.5 mm into it: no CCD, its four corners found deep.
  Drop d = drop(1e-6, 0.5e-3);
  const std::vector<BodyPair> resting{{0, 1}};
  ImpactMap meeting;
  const Sweep sweep = sweep_motions(d.world(), d.participants, d.next, &resting, nullptr, &meeting);
  EXPECT_EQ(sweep.ccd_queries, 0);
  EXPECT_TRUE(sweep.deepening);
  EXPECT_EQ(sweep.tau, 1.0);
  ASSERT_EQ(meeting.at({0, 1}).size(), 4u);
  for (const ImpactPoint& hit : meeting.at({0, 1})) EXPECT_NEAR(hit.end_depth_m, 0.5e-3 - 1e-6, 1e-12);
  // The same motion not resting (no contacts at the start) is swept by the CCD.
  const Sweep swept = sweep_motions(d.world(), d.participants, d.next, nullptr, nullptr, nullptr);
  EXPECT_EQ(swept.ccd_queries, 1);
  EXPECT_NEAR(swept.tau, 1e-6 / 0.5e-3, 1e-6);
}

TEST(StepSweep, RestingPairsGoUnsweptUpToAQuarterOfTheThinnerBodyOrTheContactTolerance) {
  const WorldOptions options;
  const RigidBody a = cube("a", {0, 0, 0}, 0.2), b = cube("b", {0, 0, 0.2}, 0.004);
  EXPECT_DOUBLE_EQ(max_unswept_motion_m(options, a, a), 0.01);   // resting_unswept_motion_m
  EXPECT_DOUBLE_EQ(max_unswept_motion_m(options, a, b), 0.001);  // a quarter of 4 mm
  RigidBody bouncy = a;
  bouncy.restitution = 0.4;  // what the end check finds is held, not bounced
  EXPECT_DOUBLE_EQ(max_unswept_motion_m(options, bouncy, a), options.contact_tolerance_m);
}

}  // namespace
}  // namespace arphys::dynamics

namespace arphys::dynamics {
namespace {

TEST(StepSweep, AMotionWithoutAnEndPosePerParticipantIsRefused) {
  Drop d = drop(0.02, 0.03);
  d.next.pop_back();
  try {
    sweep_motions(d.world(), d.participants, d.next, nullptr, nullptr, nullptr);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "sweep_motions: next has 1 entries, expected 2");
  }
}

}  // namespace
}  // namespace arphys::dynamics
