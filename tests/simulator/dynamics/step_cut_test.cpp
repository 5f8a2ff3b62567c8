// After a sweep (step_cut.hpp): lifts of too-deep resting points, where to cut, kept motions.
#include "simulator/dynamics/step_cut.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "tests/simulator/dynamics/test_bodies.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

// A 0.2 m cube resting 1 um above the floor, moved drop_m down: swept as a resting pair.
struct Sunk {
  testing::StageWorld world = testing::stage_world({plane_body(), cube("cube", {0, 0, 0.1 + 1e-6})});
  const WorldModel& model = world.model;
  std::vector<BodyState>& bodies = world.state;
  const WorldOptions& options = model.options;
  std::vector<int> participants{0, 1};
  std::vector<BodyPair> resting{{0, 1}};
  std::vector<geometry::Pose> next;
  MeshCrossingMemo memo;
  WorkerPool pool{1};
  ImpactCache cache;
  ImpactMap meeting;
  Sweep sweep;
  explicit Sunk(double drop_m) {
    next = {bodies[0].X_WB, geometry::translation_pose({0, 0, 0.1 + 1e-6 - drop_m})};
    memo.placed_since_step = {0, 0};
    sweep = sweep_motions({model, bodies, memo, pool}, participants, next, &resting, &cache, &meeting);
  }
};

TEST(StepCut, ALiftMovesTheEndPoseOutToWithinTheTolerance) {
  Sunk s(0.5e-3);
  ASSERT_TRUE(s.sweep.deepening);
  ASSERT_TRUE(project_deep_points(s.model, s.bodies, s.participants, s.next, s.meeting, s.cache, s.resting));
  const double depth_m = deepest_overlap(s.model.bodies[0], s.next[0], s.model.bodies[1], s.next[1]);
  EXPECT_LE(depth_m, s.options.overlap_tolerance_m);
  // Held just under what it may end at, not lifted clear: 0.25-1 um deep.
  EXPECT_GE(depth_m, 0.25 * s.options.overlap_tolerance_m);
}

TEST(StepCut, ACutStopsWhereTheDeepeningPairIsStillWithinWhatItMayEnd) {
  // 3 um down from 1 um above: within the 1 um allowed up to 2/3 of the motion; halving
  // from the whole, half.
  Sunk s(3e-6);
  EXPECT_DOUBLE_EQ(shallow_fraction(s.model, s.bodies, s.participants, s.next, s.cache, s.meeting), 0.5);
  // An unswept pair cut mid-motion may be left as deep as the rest of a 10 ms step undoes
  // at half the depenetration speed: 0.5 mm down, 124 um deep at a quarter, where 187 um may be.
  Sunk deep(0.5e-3);
  EXPECT_DOUBLE_EQ(unswept_clear_fraction(deep.model, deep.bodies, deep.participants, deep.next, deep.cache, 1.0, 0.01),
                   0.25);
}

TEST(StepCut, MotionsAreKeptOnlyForBodiesWhoseVelocityIsExactlyTheSame) {
  Sunk s(1e-3);
  std::vector<BodyVelocity> before(2), after(2);
  before[1].v_WBcm_m_s = {0, 0, -0.1};
  after[1].v_WBcm_m_s = {0, 0, -0.1};
  std::vector<geometry::Pose> next = {s.bodies[0].X_WB, geometry::translation_pose({0, 0, 0.5})};
  EXPECT_EQ(keep_motions(s.model, s.bodies, s.participants, before, s.next, after, next), (std::vector<char>{1, 1}));
  EXPECT_TRUE(next[1].isApprox(s.next[1]));
  after[1].v_WBcm_m_s.z() = -0.1 + 1e-12;
  next[1] = geometry::translation_pose({0, 0, 0.5});
  EXPECT_EQ(keep_motions(s.model, s.bodies, s.participants, before, s.next, after, next), (std::vector<char>{1, 0}));
  EXPECT_DOUBLE_EQ(next[1].translation().z(), 0.5);
  // A sleeper is held where it is, as a static body is, whatever the solve gave it.
  s.bodies[1].asleep = true;
  EXPECT_EQ(keep_motions(s.model, s.bodies, s.participants, before, s.next, after, next), (std::vector<char>{1, 1}));
  EXPECT_DOUBLE_EQ(next[1].translation().z(), 0.5);
}

}  // namespace
}  // namespace arphys::dynamics
