// The contacts stage of a step (step_contacts.hpp): manifolds, hints, mesh crossings.
#include "simulator/dynamics/step_contacts.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tests/simulator/dynamics/test_bodies.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

struct Bodies {
  WorldModel model;
  std::vector<BodyState> bodies;
  std::vector<int> everyone;
  MeshCrossingMemo memo;
};
Bodies of(const std::vector<RigidBody>& bodies) {
  Bodies out;
  testing::StageWorld world = testing::stage_world(bodies);
  out.model = std::move(world.model);
  out.bodies = std::move(world.state);
  for (std::size_t i = 0; i < out.bodies.size(); ++i) out.everyone.push_back(static_cast<int>(i));
  out.memo.placed_since_step.assign(out.bodies.size(), 0);
  return out;
}

TEST(StepContacts, ACubeOnTheFloorRestsOnItsFourCornersAndTwoFixedBodiesHaveNone) {
  RigidBody wall = cube("wall", {0, 0, 0.1});
  wall.motion = BodyMotion::kStatic;  // fixed, touching the floor: not a pair
  Bodies scene = of({plane_body(), cube("cube", {0.5, 0, 0.1005}), wall});
  const WorkerPool pool(1);
  const std::vector<Contact> contacts =
      gather_contacts(scene.model, scene.bodies, {}, scene.memo, pool, scene.everyone, 0);
  ASSERT_EQ(contacts.size(), 4u);
  for (const Contact& c : contacts) {
    EXPECT_EQ(c.body_a, 0);
    EXPECT_EQ(c.body_b, 1);
    EXPECT_NEAR(c.feature.distance_m, 0.5e-3, 1e-12);
    EXPECT_FALSE(c.pushed_before);
  }
  // 2 mm up is beyond the 1 mm contact tolerance.
  scene.bodies[1].X_WB.translation().z() = 0.102;
  EXPECT_TRUE(gather_contacts(scene.model, scene.bodies, {}, scene.memo, pool, scene.everyone, 0).empty());
}

TEST(StepContacts, ContactsTakeTheHintsTheLastStepLeftWithinTheTolerance) {
  Bodies scene = of({plane_body(), cube("cube", {0, 0, 0.1})});
  const Eigen::Vector3d corner_W(0.1, 0.1, 0);
  ContactHints hints;
  hints.pushed_before = {{{0, 1}, corner_W + Eigen::Vector3d(0.5e-3, 0, 0)}};
  hints.warm_forces = {{{0, 1}, corner_W + Eigen::Vector3d(0.9e-3, 0, 0), {0, 0, 1.0}},
                       {{0, 1}, corner_W + Eigen::Vector3d(0.2e-3, 0, 0), {0, 0, 2.5}}};
  hints.pending_bounces = {{{0, 1}, {0, 0, 1}, 0.3}};
  const WorkerPool pool(1);
  const std::vector<Contact> contacts =
      gather_contacts(scene.model, scene.bodies, hints, scene.memo, pool, scene.everyone, 0);
  ASSERT_EQ(contacts.size(), 4u);
  int pushed = 0;
  for (const Contact& c : contacts) {
    const bool at_corner = (c.feature.point_B_W - corner_W).norm() < 1e-9;
    pushed += c.pushed_before;
    EXPECT_EQ(c.pushed_before, at_corner);
    // The nearest warm force within the tolerance; none at the other corners.
    EXPECT_DOUBLE_EQ(c.warm_force_W_N.z(), at_corner ? 2.5 : 0.0);
    // The held-back bounce along the floor's normal acts on every contact of the pair.
    EXPECT_DOUBLE_EQ(c.min_normal_velocity_m_s, 0.3);
  }
  EXPECT_EQ(pushed, 1);
  // A bounce along another normal (the pair turned) does not.
  hints.pending_bounces = {{{0, 1}, {1, 0, 0}, 0.3}};
  for (const Contact& c : gather_contacts(scene.model, scene.bodies, hints, scene.memo, pool, scene.everyone, 0))
    EXPECT_LT(c.min_normal_velocity_m_s, 0);
}

TEST(StepContacts, APlacedMeshPairThatCrossesGetsAContactThatPushesItApart) {
  const auto mesh_cube = [](const std::string& id, const Eigen::Vector3d& p) {
    return testing::mesh_cube(id, p, 0.08);
  };
  RigidBody table = mesh_cube("table", {0, 0, 0});
  table.motion = BodyMotion::kStatic;
  // Placed 1.6 mm into the table: no feature within the 1 mm tolerance shows it.
  Bodies scene = of({table, mesh_cube("cube", {0.01, 0, 0.08 - 1.6e-3})});
  scene.memo.placed_since_step = {0, 1};
  const WorkerPool pool(1);
  const std::vector<Contact> contacts =
      gather_contacts(scene.model, scene.bodies, {}, scene.memo, pool, scene.everyone, 0);
  EXPECT_EQ(scene.memo.crossing_tests, 1);
  EXPECT_EQ(scene.memo.placed_crossing.count({0, 1}), 1u);
  ASSERT_FALSE(contacts.empty());
  const Contact& push = contacts.back();
  // Up (table to cube), as deep as the cube must move to clear (to a factor of two), at
  // the cube's centre of mass so it lifts the cube instead of turning it.
  EXPECT_NEAR(push.feature.normal_W.z(), 1.0, 1e-9);
  EXPECT_LE(-push.feature.distance_m, 2 * 1.6e-3);
  EXPECT_GE(-push.feature.distance_m, 1.6e-3);
  EXPECT_LT((push.feature.point_B_W - com_W(scene.model.bodies[1], scene.bodies[1])).norm(), 1e-12);
  // Lifted out, it is apart: no longer a placed crossing.
  scene.bodies[1].X_WB.translation().z() = 0.0805;
  gather_contacts(scene.model, scene.bodies, {}, scene.memo, pool, scene.everyone, 0);
  EXPECT_EQ(scene.memo.placed_crossing.count({0, 1}), 0u);
  EXPECT_EQ(scene.memo.apart_at.count({0, 1}), 1u);
}

}  // namespace
}  // namespace arphys::dynamics
