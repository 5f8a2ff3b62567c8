// Deactivation (WorldOptions::sleep_after_s): bodies at rest stop costing anything, and
// wake when something moving reaches them.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/world.hpp"
#include "tests/simulator/dynamics/test_bodies.hpp"

namespace arphys::dynamics {
namespace {

using testing::cube;
using testing::plane_body;

WorldOptions sleepy() {
  WorldOptions options;
  options.sleep_after_s = 0.2;
  return options;
}

// The deepest two bodies overlap at their current poses (0: apart or touching).
double overlap_m(const World& world, int a, int b) {
  double deepest = 0;
  const auto& A = world.body_copy(a);
  const auto& B = world.body_copy(b);
  for (const auto& point : collision::contact_manifold(A.shape, A.X_WB, B.shape, B.X_WB, 0.0))
    deepest = std::max(deepest, -point.distance_m);
  return deepest;
}

// A box resting on the floor at the origin (it falls asleep) and a kinematic box 0.5 m
// behind it along -x that follows `trajectory` (an empty one: it stays where it is put).
struct SleeperAndPusher {
  World world;
  int target = -1, pusher = -1;
};
SleeperAndPusher sleeper_and_pusher(const WorldOptions& options, KinematicTrajectory trajectory = {}) {
  SleeperAndPusher scene{World(options)};
  scene.world.add_body(plane_body());
  scene.target = scene.world.add_body(cube("target", {0, 0, 0.1 + 1e-6}));
  RigidBody pusher = cube("pusher", {-0.5, 0, 0.1 + 1e-6});
  pusher.motion = BodyMotion::kKinematic;
  pusher.trajectory = std::move(trajectory);
  scene.pusher = scene.world.add_body(pusher);
  return scene;
}

TEST(Sleeping, ABoxAtRestFallsAsleepAndCostsNothing) {
  World world(sleepy());
  world.add_body(plane_body());
  const int box = world.add_body(cube("box", {0, 0, 0.15}));  // 5 cm above the floor
  StepReport report;
  int steps_to_sleep = 0;
  for (; steps_to_sleep < 1000 && !world.asleep(box); ++steps_to_sleep) report = world.step(0.01);
  ASSERT_TRUE(world.asleep(box));
  // It fell 5 cm (0.1 s), settled, and slept 0.2 s after it last moved.
  EXPECT_GT(steps_to_sleep, 25);
  EXPECT_LT(steps_to_sleep, 45);
  EXPECT_EQ(report.bodies_asleep, 1);
  const geometry::Pose X_asleep = world.body_state(box).X_WB;
  for (int k = 0; k < 100; ++k) {
    report = world.step(0.01);
    EXPECT_EQ(report.contacts, 0) << "a sleeper's contacts are not gathered or solved";
    EXPECT_EQ(report.ccd_queries, 0);
  }
  EXPECT_TRUE(world.asleep(box));
  EXPECT_TRUE(world.body_state(box).X_WB.matrix() == X_asleep.matrix()) << "a sleeper does not creep";
  EXPECT_TRUE(world.body_state(box).v_WBcm_m_s.isZero());
  EXPECT_NEAR(world.body_state(box).X_WB.translation().z(), 0.1, 2e-6);
}

TEST(Sleeping, WithoutTheOptionNothingSleeps) {
  World world;
  world.add_body(plane_body());
  const int box = world.add_body(cube("box", {0, 0, 0.1 + 1e-6}));
  StepReport report;
  for (int k = 0; k < 200; ++k) report = world.step(0.01);
  EXPECT_FALSE(world.asleep(box));
  EXPECT_EQ(report.bodies_asleep, 0);
  EXPECT_GT(report.contacts, 0);
}

// A tracked box moving at 0.5 m/s reaches a sleeping box: it wakes in time to be pushed,
// never overlapped, and moves off at the pusher's speed.
TEST(Sleeping, AMovingTrackedBodyWakesASleeperInTimeToPushIt) {
  WorldOptions options = sleepy();
  KinematicTrajectory trajectory;
  trajectory.add(0.0, geometry::translation_pose({-0.5, 0, 0.1 + 1e-6}));
  trajectory.add(1.0, geometry::translation_pose({-0.5, 0, 0.1 + 1e-6}));  // still for 1 s
  trajectory.add(2.0, geometry::translation_pose({0.0, 0, 0.1 + 1e-6}));   // then 0.5 m/s
  trajectory.add(2.4, geometry::translation_pose({0.2, 0, 0.1 + 1e-6}));
  auto [world, target, p] = sleeper_and_pusher(options, trajectory);
  double deepest = 0;
  bool slept = false;
  for (int k = 0; k < 240; ++k) {
    world.step(0.01);
    slept |= world.asleep(target);
    deepest = std::max(deepest, overlap_m(world, p, target));
    if (k == 90) {
      EXPECT_TRUE(world.asleep(target)) << "asleep while the pusher stands still";
    }
  }
  EXPECT_TRUE(slept);
  EXPECT_FALSE(world.asleep(target));
  EXPECT_LE(deepest, options.overlap_tolerance_m);
  // Pushed from x = 0 by the pusher's face (which ends at x = 0.2 - 0.1 = 0.1).
  EXPECT_GT(world.body_state(target).X_WB.translation().x(), 0.19);
  EXPECT_NEAR(world.body_state(target).v_WBcm_m_s.x(), 0.5, 0.05);
}

// A box dropped onto a sleeping stack wakes the box it lands on, and that one the box
// it rests on: the stack takes the blow together, nothing overlaps, and it sleeps again.
TEST(Sleeping, ABodyLandingOnASleepingStackWakesItThroughItsContacts) {
  WorldOptions options = sleepy();
  World world(options);
  world.add_body(plane_body());
  const int bottom = world.add_body(cube("bottom", {0, 0, 0.1 + 1e-6}));
  const int top = world.add_body(cube("top", {0, 0, 0.3 + 2e-6}));
  for (int k = 0; k < 60; ++k) world.step(0.01);
  ASSERT_TRUE(world.asleep(bottom) && world.asleep(top));
  // Far above the stack's reach, then landing on it at about 2 m/s.
  RigidBody dropped = cube("dropped", {0, 0, 0.7});
  const int d = world.add_body(dropped);
  bool bottom_woke = false;
  double deepest = 0;
  for (int k = 0; k < 150; ++k) {
    world.step(0.01);
    bottom_woke |= !world.asleep(bottom);
    deepest = std::max({deepest, overlap_m(world, d, top), overlap_m(world, top, bottom), overlap_m(world, 0, bottom)});
  }
  EXPECT_TRUE(bottom_woke);
  EXPECT_LE(deepest, options.overlap_tolerance_m);
  EXPECT_TRUE(world.asleep(bottom) && world.asleep(top) && world.asleep(d)) << "asleep again once all three rest";
  EXPECT_GT(world.body_state(d).X_WB.translation().z(), 0.49);  // on top of the stack
}

// Removing a body renumbers the others: the sleepers' contact partners follow, so the
// chain still wakes the right bodies.
TEST(Sleeping, RemovingABodyKeepsTheSleepersPartnersRight) {
  World world(sleepy());
  const int loose = world.add_body(cube("loose", {3, 0, 0.1 + 1e-6}));  // index 0, removed below
  world.add_body(plane_body());
  world.add_body(cube("bottom", {0, 0, 0.1 + 1e-6}));
  world.add_body(cube("top", {0, 0, 0.3 + 2e-6}));
  for (int k = 0; k < 60; ++k) world.step(0.01);
  world.remove_body(loose);
  const int bottom = world.find("bottom"), top = world.find("top");
  ASSERT_TRUE(world.asleep(bottom) && world.asleep(top));
  // Placing the top box (as crash recovery does) wakes it, and the bottom box it touches.
  world.place_body(top, world.body_state(top).X_WB);
  EXPECT_FALSE(world.asleep(top));
  EXPECT_FALSE(world.asleep(bottom)) << "woken through the top box's contact";
}

// A tracked box placed (moved without a motion, as a naive coupling or a recovery does)
// 5 mm into a sleeping box wakes it: the sleeper is pushed out, at most at the
// depenetration speed.
// (Only a body's own placing woke it: held as a fixed body, the sleeper and the kinematic
// box met as two non-dynamic bodies, and they stayed 5 mm inside each other for good.)
TEST(Sleeping, ABodyPlacedIntoASleeperWakesIt) {
  WorldOptions options = sleepy();
  auto [world, target, p] = sleeper_and_pusher(options);
  for (int k = 0; k < 40; ++k) world.step(0.01);
  ASSERT_TRUE(world.asleep(target));
  world.place_body(p, geometry::translation_pose({-0.2 + 0.005, 0, 0.1 + 1e-6}));
  ASSERT_NEAR(overlap_m(world, p, target), 0.005, 1e-5);
  world.step(0.01);
  EXPECT_FALSE(world.asleep(target));
  for (int k = 0; k < 30; ++k) world.step(0.01);
  EXPECT_LE(overlap_m(world, p, target), options.overlap_tolerance_m);
  EXPECT_GT(world.body_state(target).X_WB.translation().x(), 0.005 - options.overlap_tolerance_m);
  // Pushed apart, not launched: it slides off (a frictionless floor) no faster than that.
  EXPECT_LE(world.body_state(target).v_WBcm_m_s.norm(), options.max_depenetration_speed_m_s + 1e-9);
}

}  // namespace
}  // namespace arphys::dynamics
