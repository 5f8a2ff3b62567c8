// Bodies built from scene files: the bunny of application 2 on its table.
#include "simulator/scene/scene_world.hpp"

#include <gtest/gtest.h>

#include "configs/loader/scene_config.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/geometry/mass_properties.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::dynamics {
namespace {

const std::string kScenes = std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/";

// Lowest point of a body's mesh in the world, metres.
double lowest_z(const RigidBody& body) {
  double lowest = 1e9;
  for (const auto& v : body.shape.triangles()->mesh().vertices_m) lowest = std::min(lowest, (body.X_WB * v).z());
  return lowest;
}

// Application 2's table and box, without bunnies.
World table_and_box() {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  for (auto& o : scene.objects) o.spawn_at_start.clear();
  World world = arphys::scene::build_world(scene);
  world.remove_body(world.find("bunny"));
  return world;
}

// Adds an 8 cm, 0.2 kg cube as a triangle mesh, tilted 2.3 deg about x (one bottom edge
// lowest), its lowest point at lowest_z_m over the table top (negative: inside the table).
int add_tilted_mesh_cube(World& world, double lowest_z_m) {
  RigidBody cube;
  cube.id = "mesh-cube";
  const Eigen::Vector3d size_m(0.08, 0.08, 0.08);
  cube.shape = collision::Shape::mesh(std::make_shared<const collision::CollisionMesh>(geometry::make_box_mesh(size_m)));
  cube.mass = geometry::with_mass(geometry::box_mass_properties(size_m, 1000), 0.2);
  cube.X_WB = geometry::Pose::Identity();
  cube.X_WB.linear() = Eigen::Quaterniond(0.9998, 0.02, 0, 0).normalized().toRotationMatrix();
  cube.X_WB.translation() = Eigen::Vector3d(-0.2, -0.2, lowest_z_m - lowest_z(cube));
  return world.add_body(std::move(cube));
}

// The scanned bunny has holes in its base. Dropped upright from a few millimetres, it rests
// on its open mesh's vertices (a manifold that dropped them, as
// DiscreteQuery.OpenSurfaceVerticesRestingOnASolidAreContacts guards against, let it sink
// through the table from 2, 5 and 10 mm).
TEST(SceneWorld, UprightBunnyDroppedFromLowHeightsRestsOnTheTable) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  for (auto& o : scene.objects) o.spawn_at_start.clear();
  const config::ObjectConfig* bunny = scene.find_object("bunny");
  ASSERT_NE(bunny, nullptr);
  for (double gap_m : {0.0005, 0.002, 0.005, 0.01, 0.02}) {
    World world = arphys::scene::build_world(scene);
    world.remove_body(world.find("bunny"));
    geometry::Pose X = geometry::make_pose({0, 0, 0}, {0.7071067811865476, 0.7071067811865476, 0, 0});
    RigidBody body = arphys::scene::make_instance(*bunny, "b", X, {0, 0, 0}, {0, 0, 0});
    X.translation().z() = gap_m - lowest_z(body);
    body.X_WB = X;
    const int index = world.add_body(std::move(body));
    for (int k = 0; k < 100; ++k) world.step(0.01);
    EXPECT_GT(lowest_z(world.body_copy(index)), -1e-5) << "dropped from " << gap_m << " m";
    EXPECT_LT(lowest_z(world.body_copy(index)), 1e-3) << "dropped from " << gap_m << " m";
  }
}

// A mesh sliding slowly on the box table (resting, moving less than the contact
// tolerance a step) has its motion checked at the end (do the surfaces cross?), not
// swept by the CCD, which for surfaces a micrometre apart is the most expensive query
// there is (in application 2's pile of bunnies, 40 % of the simulator's time). The check
// must hold it as well: never crossing, gliding on the table. (A cube as a triangle mesh,
// frictionless, 0.5 mm a step.)
TEST(SceneWorld, AMeshSlidingSlowlyOnTheTableIsCheckedAtTheEndOfItsMotionNotSwept) {
  World world = table_and_box();
  const int index = add_tilted_mesh_cube(world, 0.0005);  // an edge 0.5 mm up
  for (int k = 0; k < 100; ++k) world.step(0.01);  // lands and settles
  const BodyModel& body = world.body_model(index);
  const BodyState& now = world.body_state(index);  // (a reference: it follows the steps)
  const int table_index = world.find("table");
  const BodyModel& table = world.body_model(table_index);
  const geometry::Pose X_WT = world.body_state(table_index).X_WB;
  const Eigen::Vector3d rest = now.X_WB.translation();
  EXPECT_NEAR(rest.z(), 0.04, 1e-4);  // on its face, not on an edge
  world.set_velocity(index, Eigen::Vector3d(0.05, 0, 0), world.body_state(index).w_WB_rad_s);
  int swept = 0;
  for (int k = 0; k < 100; ++k) {
    swept += world.step(0.01).ccd_queries;
    ASSERT_FALSE(collision::intersects(*table.shape.triangles(), X_WT, *body.shape.triangles(), now.X_WB))
        << "step " << k;
    ASSERT_NEAR(now.X_WB.translation().z(), rest.z(), 1e-5) << "step " << k;
  }
  EXPECT_EQ(swept, 0);  // (swept, it would be one query a step)
  EXPECT_NEAR(now.X_WB.translation().x() - rest.x(), 0.05, 1e-3);
}

// A spinning bunny lowered onto a still one until they touch, as a step cut at their
// time of impact leaves them (picometres apart), then left to fall and turn on it. The
// CCD, touching at the start, times nothing after it: without the end checks, the turning
// bunny's other features go through the still one's surface (in the thrown-bunny scene,
// resting pairs sink 5 mm into each other over ten steps). No step may end with the
// bunnies deeper inside each other than the world's overlap tolerance (1 um, measured by
// their pieces' manifolds).
TEST(SceneWorld, TouchingBunniesTurningIntoEachOtherNeverEndAStepCrossing) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  const config::ObjectConfig* bunny = scene.find_object("bunny");
  ASSERT_NE(bunny, nullptr);
#ifdef ARPHYS_UNDER_SANITIZERS
  const int kSteps = 10;  // (the crossings came in the first eight steps)
#else
  const int kSteps = 50;
#endif
  int crossed = 0;
  for (const Eigen::Vector3d axis : {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()}) {
    for (const double w_rad_s : {-10.0, -5.0, 5.0, 10.0}) {
      World world;
      const geometry::Pose upright = geometry::make_pose({0, 0, 0}, {0.7071067811865476, 0.7071067811865476, 0, 0});
      RigidBody still = arphys::scene::make_instance(*bunny, "still", upright, {0, 0, 0}, {0, 0, 0});
      still.motion = BodyMotion::kStatic;
      world.add_body(still);
      // Lowered from 30 cm above until the surfaces touch.
      geometry::Pose away = upright;
      away.translation() += Eigen::Vector3d(0.01, 0.01, 0.3);
      const RigidBody probe = arphys::scene::make_instance(*bunny, "turning", away, {0, 0, 0}, {0, 0, 0});
      const geometry::ScrewMotion slide(away, upright), rest(upright, upright);
      const auto toi = collision::time_of_impact(still.shape, rest, probe.shape, slide);
      ASSERT_TRUE(toi.collides);
      const geometry::Pose touching = slide.pose_at(toi.time_of_impact);
      const collision::CollisionMesh& mesh = *still.shape.triangles();
      ASSERT_FALSE(collision::intersects(mesh, upright, mesh, touching));
      ASSERT_LT(collision::separation(mesh, upright, mesh, touching, 1e-6).distance_m, 1e-8);
      const int turning = world.add_body(arphys::scene::make_instance(*bunny, "turning", touching, {0, 0, 0}, w_rad_s * axis));
      for (int k = 0; k < kSteps; ++k) {
        world.step(0.02);
        const RigidBody& body = world.body_copy(turning);
        ASSERT_TRUE(body.X_WB.matrix().allFinite());
        double deepest_m = 0;
        for (const auto& point : collision::contact_manifold(still.shape, upright, body.shape, body.X_WB, 0.0))
          deepest_m = std::max(deepest_m, -point.distance_m);
        crossed += deepest_m > world.options().overlap_tolerance_m;
      }
    }
  }
  EXPECT_EQ(crossed, 0) << "steps that ended with the bunnies deeper inside each other than the tolerance";
}

// Two bunnies crossing by 0.3 mm (a squeezed pile leaves such pairs). A mesh's manifold
// gives the crossing features distance 0, which a solve undoes at the resting gap per
// step: before the crossing contact, such a pair stayed crossed for hundreds of steps.
// Now it is pushed apart at the depenetration speed, no faster, and clear within ten.
TEST(SceneWorld, CrossedBunniesArePushedApartAtTheDepenetrationSpeed) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  const config::ObjectConfig* bunny = scene.find_object("bunny");
  ASSERT_NE(bunny, nullptr);
  WorldOptions options;
  options.gravity_m_s2.setZero();
  World world(options);
  const geometry::Pose upright = geometry::make_pose({0, 0, 0}, {0.7071067811865476, 0.7071067811865476, 0, 0});
  RigidBody still = arphys::scene::make_instance(*bunny, "still", upright, {0, 0, 0}, {0, 0, 0});
  still.motion = BodyMotion::kStatic;
  world.add_body(still);
  // Slid in along x until the surfaces touch, then 0.3 mm further.
  geometry::Pose away = upright;
  away.translation().x() = 0.2;
  const RigidBody probe = arphys::scene::make_instance(*bunny, "pushed", away, {0, 0, 0}, {0, 0, 0});
  const geometry::ScrewMotion slide(away, upright), rest(upright, upright);
  const auto toi = collision::time_of_impact(still.shape, rest, probe.shape, slide);
  ASSERT_TRUE(toi.collides);
  geometry::Pose crossed = slide.pose_at(toi.time_of_impact);
  crossed.translation().x() -= 3e-4;
  const collision::CollisionMesh& mesh = *still.shape.triangles();
  ASSERT_TRUE(collision::intersects(mesh, upright, mesh, crossed));
  const int pushed = world.add_body(arphys::scene::make_instance(*bunny, "pushed", crossed, {0, 0, 0}, {0, 0, 0}));
  int crossing_steps = 0;
  double fastest_m_s = 0;
  for (int k = 0; k < 10; ++k) {
    world.step(0.01);
    const RigidBody& body = world.body_copy(pushed);
    crossing_steps += collision::intersects(mesh, upright, mesh, body.X_WB);
    fastest_m_s = std::max(fastest_m_s, body.v_WBcm_m_s.norm());
  }
  EXPECT_LT(crossing_steps, 10);
  EXPECT_FALSE(collision::intersects(mesh, upright, mesh, world.body_state(pushed).X_WB));
  EXPECT_GT(fastest_m_s, 0.01);  // pushed out, not left to the resting gap's micrometre a step
  EXPECT_LE(fastest_m_s, 1.5 * world.options().max_depenetration_speed_m_s);  // and not launched
}

// A mesh cube placed with its lowest corner 0.5 to 8 mm into the box table (a scene
// file's or a spawn's mistake; stepped bodies never get there). Deeper than the contact
// tolerance no feature is near, and the cube fell through the table from 1.6 mm; from
// 3 mm the push-out, acting at the crossing triangles' middle (the table top's spans the
// table), turned it about its rim instead of lifting it. It rises at the depenetration
// speed, no faster, and rests on the table, at most the scene's contact gap above it.
TEST(SceneWorld, AMeshPlacedDeepInsideTheTableIsPushedOutAndRests) {
  for (const double depth_m : {0.5e-3, 1.6e-3, 3e-3, 6e-3, 8e-3}) {
    World world = table_and_box();
    const int index = add_tilted_mesh_cube(world, -depth_m);
    double fastest_m_s = 0;  // while it is being pushed out (out, it tips flat, as it would)
    for (int k = 0; k < 100; ++k) {
      const bool inside = lowest_z(world.body_copy(index)) < 0;
      world.step(0.01);
      if (inside) fastest_m_s = std::max(fastest_m_s, world.body_state(index).v_WBcm_m_s.norm());
    }
    const RigidBody& body = world.body_copy(index);
    const double rest_gap_m = world.options().contact_gap_m + 1e-6;
    EXPECT_GE(lowest_z(body), 0) << "placed " << depth_m << " m deep";
    EXPECT_LE(lowest_z(body), rest_gap_m) << "placed " << depth_m << " m deep";
    EXPECT_LT(body.v_WBcm_m_s.norm(), 1e-6) << "placed " << depth_m << " m deep";
    EXPECT_LE(fastest_m_s, 1.5 * world.options().max_depenetration_speed_m_s) << "placed " << depth_m << " m deep";
    // Moved there again, as a recovered body is (World::place_body): the same.
    geometry::Pose again = body.X_WB;
    again.translation().z() -= depth_m;
    world.place_body(index, again);
    for (int k = 0; k < 100; ++k) world.step(0.01);
    EXPECT_GE(lowest_z(world.body_copy(index)), 0) << "placed again " << depth_m << " m deep";
    EXPECT_LE(lowest_z(world.body_copy(index)), rest_gap_m) << "placed again " << depth_m << " m deep";
  }
}

// A scene that allows 10 um of gap and overlap gets them; one that says nothing, the
// world's defaults (1 um each).
TEST(SceneWorld, ContactGapAndOverlapToleranceComeFromTheScene) {
  config::SceneConfig scene = config::load_scene(kScenes + "drop100.yaml");
  EXPECT_DOUBLE_EQ(arphys::scene::world_options_of(scene).contact_gap_m, WorldOptions{}.contact_gap_m);
  EXPECT_DOUBLE_EQ(arphys::scene::world_options_of(scene).overlap_tolerance_m, WorldOptions{}.overlap_tolerance_m);
  scene.contact_gap_m = 1e-5;
  scene.overlap_tolerance_m = 2e-5;
  const World world = arphys::scene::build_world(scene);
  EXPECT_DOUBLE_EQ(world.options().contact_gap_m, 1e-5);
  EXPECT_DOUBLE_EQ(world.options().overlap_tolerance_m, 2e-5);
}

TEST(SceneWorld, PlacingABodyAtANonFinitePoseIsRefusedByName) {
  World world;
  RigidBody box;
  box.id = "crate";
  box.shape = collision::Shape::box({0.1, 0.1, 0.1});
  box.mass = geometry::with_mass(geometry::box_mass_properties({0.1, 0.1, 0.1}, 1000), 1.0);
  const int index = world.add_body(box);
  geometry::Pose bad = geometry::Pose::Identity();
  bad.translation().x() = std::nan("");
  try {
    world.place_body(index, bad);
    FAIL() << "a NaN pose was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("crate"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(world.body_state(index).X_WB.matrix().allFinite());
}

}  // namespace
}  // namespace arphys::dynamics
