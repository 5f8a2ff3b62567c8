// Defined behaviour on bad input and hard cases: never a crash, never NaN, never a launch.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/world.hpp"
#include "simulator/geometry/mass_properties.hpp"
#include "simulator/geometry/triangle_mesh.hpp"
#include "simulator/scene/scene_world.hpp"
#include "tests/simulator/dynamics/test_bodies.hpp"
#include "tests/support/thrown.hpp"

namespace arphys::dynamics {
namespace {

using geometry::Pose;

using testing::cube;
using testing::plane_body;

TEST(WorldRobustness, BadBodiesAreRejectedByName) {
  World world;
  RigidBody nan_pose = cube("nan-box", {0, 0, 1});
  nan_pose.X_WB.translation().x() = std::numeric_limits<double>::quiet_NaN();
  try {
    world.add_body(nan_pose);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nan-box"), std::string::npos) << e.what();
  }
  RigidBody massless = cube("massless", {0, 0, 1});
  massless.mass.mass_kg = 0;
  EXPECT_THROW(world.add_body(massless), std::invalid_argument);
  world.add_body(cube("a", {0, 0, 1}));
  EXPECT_THROW(world.add_body(cube("a", {1, 0, 1})), std::invalid_argument);  // duplicate id
  EXPECT_THROW(world.step(0.0), std::invalid_argument);
  EXPECT_THROW(world.step(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

// Options out of range are refused at construction, by name and value: a NaN compares
// false with every bound and would otherwise switch checks off unseen.
TEST(WorldRobustness, BadOptionsAreRejectedByName) {
  EXPECT_NO_THROW(World{});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto message = [](const WorldOptions& options) -> std::string {
    try {
      World world(options);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  WorldOptions options;
  options.overlap_tolerance_m = nan;
  EXPECT_NE(message(options).find("overlap_tolerance_m is nan"), std::string::npos) << message(options);
  options = {};
  options.resting_unswept_motion_m = -1e-3;
  EXPECT_NE(message(options).find("resting_unswept_motion_m is -0.001"), std::string::npos) << message(options);
  options = {};
  options.contact_gap_m = 2e-3;  // beyond contact_tolerance_m: resting contacts would be lost
  EXPECT_NE(message(options).find("contact_gap_m is 0.002, expected less than contact_tolerance_m"), std::string::npos)
      << message(options);
  options = {};
  options.max_events_per_step = 0;
  EXPECT_NE(message(options).find("max_events_per_step is 0"), std::string::npos) << message(options);
  options = {};
  options.solver.iterations = 0;
  EXPECT_NE(message(options).find("solver.iterations is 0"), std::string::npos) << message(options);
  options = {};
  options.solver.provisional_friction_sweeps = 0;
  EXPECT_NE(message(options).find("solver.provisional_friction_sweeps is 0"), std::string::npos) << message(options);
  options = {};
  options.ccd.time_tolerance = 0;
  EXPECT_NE(message(options).find("ccd.time_tolerance is 0"), std::string::npos) << message(options);
  options = {};
  options.gravity_m_s2.x() = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(options).find("gravity_m_s2"), std::string::npos) << message(options);
  options = {};
  options.max_body_speed_m_s = std::numeric_limits<double>::infinity();  // no cap: allowed
  EXPECT_EQ(message(options), "");
}

TEST(WorldRobustness, RestingContactCausesNoEvents) {
  World world;
  world.add_body(plane_body());
  const int b = world.add_body(cube("box", {0, 0, 0.1}));
  int events = 0;
  for (int k = 0; k < 2000; ++k) {
    const StepReport report = world.step(1e-3);
    events += report.events;
    ASSERT_FALSE(report.events_capped);
  }
  EXPECT_EQ(events, 0);
  EXPECT_NEAR(world.body_state(b).X_WB.translation().z(), 0.1 + world.options().contact_gap_m, 1e-12);
}

// Boxes resting flat on the floor, frictionless: each one's four corner rows are found
// in one active-set iteration, by starting from the rows gravity would violate (a cold
// start adds them one at a time, one factorisation each: in the drop1000 pile the
// exact solver did twice the work, 11,300 against 7,400 iterations per step). Still exact.
TEST(WorldRobustness, RestingBoxesAreSolvedInOneActiveSetIterationEach) {
  World world;
  world.add_body(plane_body());
  for (int i = 0; i < 10; ++i) world.add_body(cube("box" + std::to_string(i), {0.5 * i, 0, 0.1 + 1e-6}));
  for (int k = 0; k < 20; ++k) world.step(1e-3);
  const StepReport report = world.step(1e-3);
  EXPECT_EQ(report.contacts, 40);
  EXPECT_EQ(report.events, 0);
  EXPECT_LE(report.solver_iterations, 10);
  EXPECT_LT(report.kkt_residual_m_s, 1e-9);
  EXPECT_NEAR(world.body_copies().back().X_WB.translation().z(), 0.1 + 1e-6, 1e-9);
}

// A resting stack falls as one under gravity, so only its ground rows are violated by
// the unconstrained motion; the rows between boxes are found from the previous step's
// solve (ContactRow::pushed_before): one active-set iteration per step, where without
// that they join one per iteration (5 here).
TEST(WorldRobustness, RestingStackIsSolvedInOneIterationFromThePreviousStep) {
  World world;
  world.add_body(plane_body());
  const double gap = world.options().contact_gap_m;
  for (int i = 0; i < 3; ++i) world.add_body(cube("box" + std::to_string(i), {0, 0, 0.1 + 0.2 * i + gap * (i + 1)}));
  for (int k = 0; k < 20; ++k) world.step(1e-3);
  const StepReport report = world.step(1e-3);
  EXPECT_EQ(report.contacts, 12);
  EXPECT_EQ(report.events, 0);
  EXPECT_EQ(report.solver_iterations, 1);
  EXPECT_LT(report.kkt_residual_m_s, 1e-9);
  EXPECT_NEAR(world.body_copies().back().X_WB.translation().z(), 0.5 + 3 * gap, 1e-9);
}

// A box spinning at 30 rad/s near its intermediate axis, free, at dt = 10 ms (0.3 rad per
// step): it tumbles, keeping its kinetic energy and its angular momentum. The explicit
// gyroscopic step made it 114 times as energetic in 5 s (320 rad/s); bunnies tumbling off
// the table then fell at twice the free-fall speed.
TEST(WorldRobustness, FreeTumblingBoxKeepsItsEnergyAndAngularMomentum) {
  WorldOptions options;
  options.gravity_m_s2.setZero();
  World world(options);
  RigidBody b = cube("tumbler", {0, 0, 0});
  b.shape = collision::Shape::box({0.3, 0.2, 0.1});
  b.mass = geometry::with_mass(geometry::box_mass_properties({0.3, 0.2, 0.1}, 1000), 1.0);
  b.w_WB_rad_s = Eigen::Vector3d(1, 30, 1);
  world.add_body(b);
  auto energy = [&] { return kinetic_energy_J(world.body_model(0), world.body_state(0)); };
  auto momentum = [&] {
    return Eigen::Vector3d(inertia_W(world.body_model(0), world.body_state(0)) * world.body_state(0).w_WB_rad_s);
  };
  const double e0 = energy();
  const Eigen::Vector3d L0 = momentum();
  double worst_energy = 0, worst_size = 0, worst_direction = 0, fastest = 0;
  for (int k = 0; k < 500; ++k) {
    world.step(0.01);
    worst_energy = std::max(worst_energy, std::abs(energy() / e0 - 1));
    worst_size = std::max(worst_size, std::abs(momentum().norm() / L0.norm() - 1));
    worst_direction = std::max(worst_direction, (momentum() - L0).norm() / L0.norm());
    fastest = std::max(fastest, world.body_state(0).w_WB_rad_s.norm());
  }
  EXPECT_LT(worst_energy, 1e-4);
  EXPECT_LT(worst_size, 1e-4);
  EXPECT_LT(worst_direction, 0.1);  // a phase error of the 0.3 rad steps, not a gain
  EXPECT_LT(fastest, 40.0);
}

// Two boxes falling side by side, tumbling into each other: the step where they strike is
// cut at the time of impact, and together they still gain exactly the momentum gravity
// gives them. (Gravity added again over the time left after every cut would make two
// bunnies falling off the table, touching and spinning, fall at twice the free-fall speed.)
TEST(WorldRobustness, StepsCutByImpactsAddGravityOnce) {
  World world;
  RigidBody left = cube("left", {-0.1 - 5e-7, 0, 0});
  RigidBody right = cube("right", {0.1 + 5e-7, 0, 0});
  left.w_WB_rad_s = Eigen::Vector3d(0, 10, 0);
  right.w_WB_rad_s = Eigen::Vector3d(0, -10, 0);
  const int a = world.add_body(left);
  const int b = world.add_body(right);
  const double mass = world.body_model(a).mass.mass_kg + world.body_model(b).mass.mass_kg;
  int events = 0;
  for (int k = 0; k < 50; ++k) {
    events += world.step(0.01).events;
    const Eigen::Vector3d momentum = world.body_model(a).mass.mass_kg * world.body_state(a).v_WBcm_m_s +
                                     world.body_model(b).mass.mass_kg * world.body_state(b).v_WBcm_m_s;
    ASSERT_NEAR(momentum.z(), -mass * 9.81 * 0.01 * (k + 1), 1e-9) << "step " << k;
    ASSERT_NEAR(momentum.head<2>().norm(), 0.0, 1e-9) << "step " << k;
  }
  EXPECT_GT(events, 0);  // or the test would not test the cut
}

// An island over max_exact_rows goes to the iterative solver, counted; smaller ones stay
// exact. (A pile of a thousand boxes leaning on each other made one exact solve take
// minutes.)
TEST(WorldRobustness, IslandsTooLargeForTheExactSolverAreSolvedIterativelyAndCounted) {
  WorldOptions options;
  options.solver.max_exact_rows = 10;
  World world(options);
  world.add_body(plane_body());
  for (int i = 0; i < 3; ++i) world.add_body(cube("stacked" + std::to_string(i), {0, 0, 0.1 + 0.2 * i + 1e-6 * i}));
  world.add_body(cube("alone", {1, 0, 0.1 + 1e-6}));
  StepReport report;
  for (int k = 0; k < 20; ++k) report = world.step(1e-3);
  EXPECT_EQ(report.contacts, 16);
  EXPECT_EQ(report.iterative_islands, 1);  // the stack's 12 rows; the lone box's 4 are exact
  EXPECT_LT(report.kkt_residual_m_s, 1e-3);
  EXPECT_NEAR(world.body_state(3).X_WB.translation().z(), 0.5 + 2e-6, 1e-5);
}

// A 1 kg ball of 5 cm radius on the x axis moving along it (the chain tests).
RigidBody ball_on_x(const std::string& id, double x_m, double v_m_s, double restitution) {
  RigidBody b;
  b.id = id;
  b.shape = collision::Shape::sphere(0.05);
  b.mass = geometry::with_mass(geometry::sphere_mass_properties(0.05, 1000), 1.0);
  b.X_WB = geometry::translation_pose({x_m, 0, 0});
  b.v_WBcm_m_s = {v_m_s, 0, 0};
  b.restitution = restitution;
  return b;
}

// Bodies that cannot meet within a step are stepped in separate groups (an impact in one
// does not cut the others' steps). A group whose re-solved motion reaches into another's
// is merged with it and both are stepped again: here A hits B, B is sent into C, which
// at the step's start was out of everyone's reach. Without the merge B would end the
// step 5 cm inside C.
TEST(WorldRobustness, AnImpactThatSendsABodyIntoAnotherGroupMergesTheGroups) {
  WorldOptions options;
  options.gravity_m_s2.setZero();
  World world(options);
  const auto ball = [](const std::string& id, double x_m, double v_m_s) { return ball_on_x(id, x_m, v_m_s, 1.0); };
  const int a = world.add_body(ball("a", 0.0, 10.0));
  const int b = world.add_body(ball("b", 0.12, 0.0));   // 2 cm ahead of a
  const int c = world.add_body(ball("c", 0.25, 0.0));   // 3 cm beyond b: out of a's and b's first sweeps
  const StepReport report = world.step(0.01);
  EXPECT_FALSE(report.events_capped);
  const auto& bodies = world.body_copies();
  EXPECT_GE((bodies[b].X_WB.translation() - bodies[a].X_WB.translation()).norm(), 0.1 - 1e-6);
  EXPECT_GE((bodies[c].X_WB.translation() - bodies[b].X_WB.translation()).norm(), 0.1 - 1e-6);
  // An elastic chain of equal masses: the speed ends in c.
  EXPECT_NEAR(bodies[c].v_WBcm_m_s.x(), 10.0, 0.1);
  EXPECT_NEAR(bodies[a].v_WBcm_m_s.x() + bodies[b].v_WBcm_m_s.x() + bodies[c].v_WBcm_m_s.x(), 10.0, 1e-9);
}

// Below WorldOptions::sequential_bounce_restitution a chained bounce is not cut at: b,
// struck by a within the step, meets c and the step's solve keeps them from crossing, and the
// two part at the next step's start with the bounce b missed (restitution 0.4 of the 7 m/s
// a gave it). Momentum is kept and no energy made; c leaves b as it would have, a step late.
// Without the held-back bounce c left b at 1.2 m/s (the restitution of what was left of the
// approach), not 2.8.
TEST(WorldRobustness, ABounceAChainBroughtAboutIsHeldBackOneStepNotCut) {
  WorldOptions options;
  options.gravity_m_s2.setZero();
  World world(options);
  const auto ball = [](const std::string& id, double x_m, double v_m_s) { return ball_on_x(id, x_m, v_m_s, 0.4); };
  const int a = world.add_body(ball("a", 0.0, 10.0));
  const int b = world.add_body(ball("b", 0.12, 0.0));
  const int c = world.add_body(ball("c", 0.25, 0.0));
  EXPECT_EQ(world.step(0.01).events, 0);
  world.step(0.01);
  const auto& bodies = world.body_copies();
  const auto v = [&](int i) { return bodies[i].v_WBcm_m_s.x(); };
  EXPECT_NEAR(v(a) + v(b) + v(c), 10.0, 1e-9);
  EXPECT_LT(v(a) * v(a) + v(b) * v(b) + v(c) * v(c), 100.0);
  EXPECT_NEAR(v(c) - v(b), 0.4 * 7.0, 0.05);
  EXPECT_GE(v(b), v(a));
  EXPECT_GE((bodies[c].X_WB.translation() - bodies[b].X_WB.translation()).norm(), 0.1 - 1e-6);
}

// A step cut at a time of impact goes on from there; the pairs whose motion the cut did
// not change keep their CCD answers (a body the solve after the cut leaves as it was goes
// on along the same screw motion): here an elastic chain a -> b -> c is cut where b, struck
// within the step, meets c, and a row of balls behind a, in the chain's group (their
// boxes overlap) and moving but never touching, is not swept again.
TEST(WorldRobustness, ACutSweepsOnlyThePairsItChanged) {
  constexpr int kRowBalls = 6;
  WorldOptions options;
  options.gravity_m_s2.setZero();
  World world(options);
  auto ball = [](const std::string& id, double x_m, double y_m, double v_m_s) {
    RigidBody b;
    b.id = id;
    b.shape = collision::Shape::sphere(0.05);
    b.mass = geometry::with_mass(geometry::sphere_mass_properties(0.05, 1000), 1.0);
    b.X_WB = geometry::translation_pose({x_m, y_m, 0});
    b.v_WBcm_m_s = {v_m_s, 0, 0};
    b.restitution = 1.0;
    return b;
  };
  const int a = world.add_body(ball("a", 0.0, 0.0, 10.0));
  world.add_body(ball("b", 0.12, 0.0, 0.0));  // 2 cm ahead of a
  const int c = world.add_body(ball("c", 0.25, 0.0, 0.0));  // 3 cm beyond b
  // A zigzag row behind a, 11.3 cm apart diagonally (their boxes overlap) and closing
  // 1 cm of that over the step: they move relative to each other, so their pairs are
  // swept, but do not touch.
  std::vector<int> row;
  for (int k = 1; k <= kRowBalls; ++k) {
    RigidBody r = ball("row" + std::to_string(k), -0.08 * k, k % 2 ? 0.08 : 0.0, 0.0);
    r.v_WBcm_m_s = {0, k % 2 ? -0.5 : 0.5, 0};
    row.push_back(world.add_body(r));
  }
  const StepReport report = world.step(0.01);
  EXPECT_EQ(report.events, 1);
  const auto& bodies = world.body_copies();
  EXPECT_NEAR(bodies[c].v_WBcm_m_s.x(), 10.0, 0.1);
  EXPECT_NEAR(bodies[a].v_WBcm_m_s.norm(), 0.0, 0.1);
  for (int r : row) {  // untouched
    EXPECT_EQ(bodies[r].v_WBcm_m_s.norm(), 0.5);
    EXPECT_NEAR(bodies[r].X_WB.translation().y(), (r - c) % 2 ? 0.075 : 0.005, 1e-15);
  }
  // The row's pairs (a with the first, each with the next) are swept once: 11 queries in
  // all; sweeping them again after the cut took 17.
  EXPECT_LE(report.ccd_queries, 17 - kRowBalls);
}

// A tumbling pile on a floor: 16 boxes dropped in 2 x 2 columns of 4, each turned by up
// to 0.3 rad about a seeded random axis (splitmix64, as the benchmark's drop scenes).
World tumbling_pile(const WorldOptions& options = {}) {
  World world(options);
  world.add_body(plane_body());
  uint64_t state = 12345;  // splitmix64, as the benchmark scenes
  auto next = [&] {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
  };
  for (int layer = 0, k = 0; layer < 4; ++layer)
    for (int x = 0; x < 2; ++x)
      for (int y = 0; y < 2; ++y, ++k) {
        RigidBody box = cube("box" + std::to_string(k), {0.35 * x, 0.35 * y, 0.2 + 0.35 * layer});
        const Eigen::Vector3d axis(2 * next() - 1, 2 * next() - 1, 2 * next() - 1);
        box.X_WB.linear() = Eigen::AngleAxisd(0.3 * next(), axis.normalized()).toRotationMatrix();
        world.add_body(box);
      }
  return world;
}

// A tumbling pile (16 boxes dropped in 2 x 2 columns of 4, each turned by up to 0.3
// rad, as the benchmark's drop scenes): boxes that touch at the start of a step and
// turn (10 rad/s) are constrained at the start, linearly, and dug 22 um into each
// other before a touching pair's end of step was checked. Now no pair ends a step
// deeper than overlap_tolerance_m.
TEST(WorldRobustness, TumblingPileEndsEveryStepWithinTheOverlapTolerance) {
  World world = tumbling_pile();
  const double tolerance = world.options().overlap_tolerance_m;
  double deepest = 0;
  for (int step = 0; step < 800; ++step) {
    world.step(1e-3);
    const auto& bodies = world.body_copies();
    for (std::size_t i = 1; i < bodies.size(); ++i)
      for (std::size_t j = i + 1; j < bodies.size(); ++j)
        for (const auto& p : collision::contact_manifold(bodies[i].shape, bodies[i].X_WB, bodies[j].shape, bodies[j].X_WB, 0.0))
          deepest = std::max(deepest, -p.distance_m);
    ASSERT_LE(deepest, tolerance) << "step " << step;
  }
}

// The pile's resting pairs that a step's motion leaves too deep (a turning box's
// linearised contacts) are lifted by moving the end poses (WorldOptions::
// project_deep_points), not by constraining the velocities and solving the step again:
// the tolerance is kept (the test above) with half the re-solves. In the frictionless
// 1000-box pile over 2 s: 1,621 re-solve rounds against 4,985, 57 cuts against 484.
TEST(WorldRobustness, TumblingPileLiftsDeepPointsByMovingPosesNotBySolvingAgain) {
  struct Run {
    int projections = 0, solves = 0, rounds = 0;
    double energy_J = 0;
  };
  const auto run = [](bool project) {
    WorldOptions options;
    options.project_deep_points = project;
    World world = tumbling_pile(options);
    Run r;
    for (int step = 0; step < 800; ++step) {
      const StepReport report = world.step(1e-3);
      r.projections += report.projections;
      r.solves += report.solver_iterations;
      r.rounds += report.impacts_resolved;
    }
    for (const auto& body : world.body_copies()) r.energy_J += body.kinetic_energy_J();
    return r;
  };
  const Run projected = run(true), resolved = run(false);
  std::printf("projected: %d projections, %d rounds, %d solver iterations, %.3g J left; re-solved: %d rounds, %d, %.3g J\n",
              projected.projections, projected.rounds, projected.solves, projected.energy_J, resolved.rounds,
              resolved.solves, resolved.energy_J);
  EXPECT_EQ(resolved.projections, 0);
  EXPECT_GT(projected.projections, 10);  // 24 with gcc 12 -O3
  // Rounds of re-solves: 17 against 32 (rounds count projections too).
  EXPECT_LT(projected.rounds - projected.projections, 0.75 * resolved.rounds);
}

// A box tumbling onto another meets it inside the step at a point whose linearised
// constraint misses the turn's second-order motion (micrometres). The re-solve now
// bounds the point by where it actually ends: the meeting is settled in the step's
// re-solves instead of cutting the step at it. (Re-solved with the same bound, the
// pile cut its steps 80 times in these 800 steps.)
TEST(WorldRobustness, TumblingMeetingsAreSettledInTheStepNotCutAt) {
  World world = tumbling_pile();
  int events = 0, impacts = 0;
  for (int step = 0; step < 800; ++step) {
    const StepReport report = world.step(1e-3);
    events += report.events;
    impacts += report.impacts_resolved;
  }
  EXPECT_GT(impacts, 10);  // the boxes do land on the floor and on each other (27-56 by compiler)
  EXPECT_LE(events, 20) << impacts << " meetings";
}

// A sphere landing on a plane meets it inside the step: the meeting (a primitive
// query's, with no mesh features) is a constraint of the step, not a cut at it (it was
// cut at, after three re-solves that could not use it).
TEST(WorldRobustness, ASphereLandingOnAPlaneIsConstrainedInTheStep) {
  World world;
  world.add_body(plane_body());
  RigidBody ball;
  ball.id = "ball";
  ball.shape = collision::Shape::sphere(0.05);
  ball.mass = geometry::with_mass(geometry::sphere_mass_properties(0.05, 1000), 1.0);
  ball.X_WB = geometry::translation_pose({0, 0, 0.0515});  // beyond the contact tolerance
  ball.v_WBcm_m_s = {0, 0, -2};  // meets the plane three quarters into the step
  const int b = world.add_body(ball);
  const StepReport report = world.step(1e-3);
  EXPECT_GE(report.impacts_resolved, 1);
  EXPECT_EQ(report.events, 0);
  const RigidBody& landed = world.body_copy(b);
  // Inelastic: it stops, as every impact, at the step boundary (the velocity update of a
  // symplectic Euler step), on or above the plane.
  EXPECT_GE(landed.X_WB.translation().z(), 0.05 - world.options().overlap_tolerance_m);
  EXPECT_LE(landed.X_WB.translation().z(), 0.0515);
  EXPECT_NEAR(landed.v_WBcm_m_s.z(), 0, 1e-3);  // inelastic: it stops
}

// A resting pair moving slowly relative to each other is held by its contacts and
// checked at the end of its motion, not swept by the CCD (whose search on surfaces 1 um
// apart was most of a 1000-box pile's step); a pair in contact closing faster than
// resting_unswept_motion_m per step is still swept, and so is one that could pass
// through a thin body unseen or should bounce.
TEST(WorldRobustness, RestingPairsAreCheckedAtTheEndNotSwept) {
  RigidBody base = cube("base", {0, 0, 0.1});
  base.motion = BodyMotion::kStatic;
  World world;
  world.add_body(base);
  const double gap = world.options().contact_gap_m;
  const int top = world.add_body(cube("top", {0, 0, 0.3 + gap}));
  world.set_velocity(top, {0.1, 0, 0}, world.body_state(top).w_WB_rad_s);  // 0.1 mm per step, frictionless
  int queries = 0;
  for (int k = 0; k < 100; ++k) queries += world.step(1e-3).ccd_queries;
  EXPECT_EQ(queries, 0);
  const RigidBody& b = world.body_copy(top);
  EXPECT_NEAR(b.X_WB.translation().x(), 0.01, 1e-12);
  EXPECT_GE(b.X_WB.translation().z(), 0.3 - world.options().overlap_tolerance_m);
  EXPECT_LE(b.X_WB.translation().z(), 0.3 + 2 * gap);

  // One step of a box sliding over `under` (its top at z = 0.2) at speed_m_s; the CCD queries it took.
  const auto sweeps = [&](const RigidBody& under, double speed_m_s, double restitution = 0) {
    WorldOptions options;
    options.resting_unswept_motion_m = 10e-3;
    World w(options);
    w.add_body(under);
    RigidBody slider = cube("slider", {0, 0, 0.3 + gap});
    slider.restitution = restitution;
    slider.v_WBcm_m_s = {speed_m_s, 0, 0};
    w.add_body(slider);
    return w.step(1e-3).ccd_queries;
  };
  // 5 mm per step over a 0.2 m box: held and checked at the end; 15 mm: swept.
  EXPECT_EQ(sweeps(base, 5), 0);
  EXPECT_GE(sweeps(base, 15), 1);
  // Over a 4 mm slab, 5 mm per step could carry a point through it between the ends:
  // swept (the bound is capped at a quarter of the thinner body's thickness, 1 mm).
  RigidBody slab = base;
  slab.shape = collision::Shape::box({0.4, 0.4, 0.004});
  slab.X_WB = geometry::translation_pose({0, 0, 0.198});
  EXPECT_GE(sweeps(slab, 5), 1);
  EXPECT_EQ(sweeps(slab, 0.5), 0);
  // A bouncing pair keeps the contact tolerance: what the end check finds is held, not bounced.
  EXPECT_GE(sweeps(base, 5, 0.5), 1);
  EXPECT_EQ(sweeps(base, 0.5, 0.5), 0);
}

// A mesh pair that a step's motion proved apart at its end poses (swept by the CCD
// without meeting, or checked at the end) is not tested for crossing again at the next
// step's start, where it is at those poses: the same test, the same answer.
TEST(WorldRobustness, MeshPairsProvenApartAtAStepsEndAreNotTestedAgain) {
  const auto mesh_cube = [](const std::string& id, const Eigen::Vector3d& p) {
    return testing::mesh_cube(id, p, 0.08);
  };
  // A cube sliding past a fixed one, 0.5 mm from it (within the contact tolerance, so a
  // pair the contact pass tests), without gravity: at 3 mm per step the CCD sweeps it, at
  // 0.5 mm per step it is a resting pair checked at the end.
  for (const double speed_m_s : {0.3, 0.05}) {
    WorldOptions options;
    options.gravity_m_s2.setZero();
    World world(options);
    RigidBody fixed = mesh_cube("fixed", {0, 0, 0});
    fixed.motion = BodyMotion::kStatic;
    world.add_body(fixed);
    const int slider = world.add_body(mesh_cube("slider", {-0.05, 0, 0.0805}));
    world.set_velocity(slider, {speed_m_s, 0, 0}, world.body_state(slider).w_WB_rad_s);
    std::vector<int> tests, queries;
    for (int k = 0; k < 20; ++k) {
      const StepReport report = world.step(0.01);
      tests.push_back(report.mesh_crossing_tests);
      queries.push_back(report.ccd_queries);
    }
    SCOPED_TRACE("speed " + std::to_string(speed_m_s) + " m/s");
    EXPECT_EQ(tests.front(), 1);  // nothing known at the first step's start
    for (int k = 1; k < 20; ++k) EXPECT_EQ(tests[k], 0) << "step " << k;
    EXPECT_EQ(queries[5], speed_m_s > 0.1 ? 1 : 0);  // (swept, or checked at the end)
    const RigidBody& b = world.body_copy(slider);
    EXPECT_NEAR(b.X_WB.translation().x(), -0.05 + 20 * 0.01 * speed_m_s, 1e-12);
    EXPECT_NEAR(b.X_WB.translation().z(), 0.0805, 1e-12);
  }
}

// A tracked box comes down onto a dynamic box lying on a static floor: the box is
// squeezed. The solve is reported infeasible and the box is neither launched nor NaN.
TEST(WorldRobustness, SqueezedBodyIsReportedNotLaunched) {
  World world;
  world.add_body(plane_body());
  RigidBody press = cube("press", {0, 0, 0.3 + 1e-3}, 0.2);
  press.motion = BodyMotion::kKinematic;
  press.trajectory.add(0.0, geometry::translation_pose({0, 0, 0.3 + 1e-3}));
  press.trajectory.add(0.2, geometry::translation_pose({0, 0, 0.25}));  // 5 cm into the box
  world.add_body(press);
  const int b = world.add_body(cube("box", {0, 0, 0.1}));
  bool infeasible = false;
  for (int k = 0; k < 300; ++k) {
    const StepReport report = world.step(1e-3);
    infeasible |= report.infeasible;
    const RigidBody& body = world.body_copy(b);
    ASSERT_TRUE(body.X_WB.matrix().allFinite()) << "step " << k;
    ASSERT_TRUE(body.v_WBcm_m_s.allFinite() && body.w_WB_rad_s.allFinite()) << "step " << k;
    ASSERT_LE(body.v_WBcm_m_s.norm(), 1.0) << "launched at step " << k;
    // Nor pressed into the floor: the press's overlap cannot be undone, the floor's
    // support still holds (it was dropped with the rest: 28 um deep by step 4).
    ASSERT_GE(body.X_WB.translation().z(), 0.1 - 1e-5) << "sank at step " << k;
  }
  EXPECT_TRUE(infeasible);
}

// The launch guard marks solver failures, not off-centre impacts. A bunny landing on one
// point of its base rightly turns part of its fall into a spin whose point speed
// (|v| + |w| r, r its bounding radius about its origin) is several times the fall's:
// measured so, the guard held back every bunny of the shipped 20-bunny scene at 56 % of
// an exact solve's motion when they landed, and the next rounds' CCD worked from that.
// Alone on the table (the same landing as in the scene): nothing held back, and its
// energy (kinetic plus potential) never grows from one step to the next.
TEST(WorldRobustness, AnOffCentreLandingIsNotMistakenForALaunch) {
  config::SceneConfig scene = config::load_scene(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunnies20.yaml");
  // The scene's first bunny, dropped from where the scene had it until the spawn height
  // was raised to clear the box (0.12 m; at 0.13 m its rocking on the table gains 30 uJ
  // in one step, 0.04 % of the fall's energy, as simultaneous restitution at several
  // points can: not a launch, but not this test's landing either).
  for (auto& object : scene.objects)
    if (object.id == "bunny") {
      object.spawn_at_start.resize(1);
      object.spawn_at_start[0].X_WB.translation().z() = 0.12;
    }
  World world = arphys::scene::build_world(scene);
  int bunny = -1;
  for (int i = 0; i < world.body_count(); ++i)
    if (world.body_model(i).is_dynamic()) bunny = i;
  ASSERT_GE(bunny, 0);
  const auto energy_J = [&] {
    const RigidBody& b = world.body_copy(bunny);
    return b.kinetic_energy_J() - b.mass.mass_kg * world.options().gravity_m_s2.dot(b.com_W());
  };
  double energy_before = energy_J(), fastest_spin = 0;
  for (int k = 0; k < 60; ++k) {
    const StepReport report = world.step(0.01);
    ASSERT_EQ(report.launches_prevented, 0) << "step " << k;
    const double energy_after = energy_J();
    ASSERT_LE(energy_after, energy_before + 1e-9) << "step " << k;
    energy_before = energy_after;
    fastest_spin = std::max(fastest_spin, world.body_state(bunny).w_WB_rad_s.norm());
  }
  EXPECT_GT(fastest_spin, 5.0);  // it did land off-centre (12 rad/s here)
  EXPECT_NEAR(com_W(world.body_model(bunny), world.body_state(bunny)).z(), 0.04, 0.02);  // and rests on the table
}

// The launch guard: a frictional bunny pile pushed by the box (the scene that produced
// NaN before the guard, bunnies20 with friction 0.5) keeps every body finite and no
// faster than a fall from the table and the box's push could make it.
TEST(WorldRobustness, FrictionalPileIsNeverLaunched) {
  config::SceneConfig scene = config::load_scene(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunnies20.yaml");
  for (auto& object : scene.objects) {
    if (object.id == "bunny") object.friction = 0.5;
  }
  World world = arphys::scene::build_world(scene);
  int prevented = 0;
#ifdef ARPHYS_UNDER_SANITIZERS
  const int steps = 40;  // the pile forms; memory and UB checks of the same paths (220 steps take > 5 min there)
#else
  const int steps = 220;
#endif
  for (int i = 0; i < steps; ++i) {
    prevented += world.step(0.01).launches_prevented;
    for (const RigidBody& b : world.body_copies()) {
      ASSERT_TRUE(b.X_WB.matrix().allFinite()) << b.id << " at step " << i;
      // Bodies past 10 m are gone in the simulator process (SimulatorCore's world
      // radius). Within it a bunny can have fallen 11 m from the table: 14.7 m/s, plus
      // its throw. (Two bunnies falling off the table touching and spinning reached
      // 25 m/s when a step cut at an impact added gravity again; fixed.)
      if (b.is_dynamic() && b.X_WB.translation().norm() <= 10.0) {
        ASSERT_LT(b.v_WBcm_m_s.norm(), 17.0) << b.id << " at step " << i;
        ASSERT_LT(b.w_WB_rad_s.norm(), 300.0) << b.id << " at step " << i;
      }
    }
  }
  std::printf("launch guard acted %d times\n", prevented);
}

TEST(WorldRobustness, EventsPerStepAreCapped) {
  WorldOptions options;
  options.max_events_per_step = 2;
  World world(options);
  world.add_body(plane_body());
  // Ten boxes falling onto the floor at once, turning: impacts in the same step.
  for (int i = 0; i < 10; ++i) {
    RigidBody b = cube("box" + std::to_string(i), {0.5 * i, 0, 0.3 + 0.01 * i});
    b.w_WB_rad_s = Eigen::Vector3d(3, 1, 0);
    b.v_WBcm_m_s = Eigen::Vector3d(0, 0, -3);
    world.add_body(b);
  }
  for (int k = 0; k < 300; ++k) {
    const StepReport report = world.step(1e-2);
    ASSERT_LE(report.events, options.max_events_per_step);
    ASSERT_LE(report.max_penetration_m, 1e-3) << "step " << k;
  }
  for (const RigidBody& body : world.body_copies()) {
    if (body.is_dynamic()) {
      EXPECT_GT(body.X_WB.translation().z(), 0.09) << body.id;  // all above the floor
    }
  }
}

}  // namespace
}  // namespace arphys::dynamics

namespace arphys::dynamics {
namespace {

// A body's state is set through World, which refuses what the body cannot take, naming it.
TEST(WorldContracts, SettersRefuseWhatABodyCannotTakeNamingIt) {
  World world;
  world.add_body(testing::plane_body());
  RigidBody offset = testing::cube("offset", {0, 0, 0.5});
  offset.mass.center_of_mass_m = {0.05, 0, 0};
  const int cube = world.add_body(offset);
  const auto message = arphys::testing::invalid_argument_message;
  EXPECT_NE(message([&] {
              world.set_velocity(0, {1, 0, 0}, {0, 0, 0});
            }).find("'floor' is not dynamic"),
            std::string::npos);
  EXPECT_NE(message([&] {
              world.set_velocity(cube, {NAN, 0, 0}, {0, 0, 0});
            }).find("'offset': non-finite"),
            std::string::npos);
  EXPECT_NE(message([&] { world.set_trajectory(cube, KinematicTrajectory()); }).find("'offset' is not kinematic"),
            std::string::npos);
  // The origin's velocity: the centre of mass 5 cm off it moves with w x r besides.
  world.set_origin_velocity(cube, {0, 0, 0}, {0, 0, 2});
  EXPECT_TRUE(world.body_state(cube).v_WBcm_m_s.isApprox(Eigen::Vector3d(0, 0.1, 0), 1e-12));
  EXPECT_TRUE(origin_velocity(world.body_model(cube), world.body_state(cube)).isZero(1e-12));
}

}  // namespace
}  // namespace arphys::dynamics
