#include "configs/loader/scene_config.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "configs/loader/config_error.hpp"

namespace arphys::config {
namespace {

const std::string kConfigs = std::string(ARPHYS_SOURCE_DIR) + "/configs/";

TEST(SceneConfig, BunnyBoxTableLoads) {
  const SceneConfig scene = load_scene(kConfigs + "scenes/bunny_box_table.yaml");
  EXPECT_EQ(scene.name, "bunny_box_table");
  ASSERT_EQ(scene.objects.size(), 3u);
  const ObjectConfig* box = scene.find_object("box");
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->role, Role::kReal);
  EXPECT_EQ(box->motion, Motion::kKinematic);
  EXPECT_EQ(box->markers.size(), 5u);
  // The marker on the +x face has its z axis along the box's +x.
  EXPECT_LT((box->markers[1].X_OM.linear().col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  EXPECT_EQ(scene.find_marker_owner("tag36h11", 2)->id, "table");
  const ObjectConfig* bunny = scene.find_object("bunny");
  EXPECT_EQ(bunny->collision.type, ShapeType::kConvexSet);
  EXPECT_NE(bunny->collision.pieces_path.find("stanford-bunny-1k-quadric.pieces.obj"), std::string::npos);
  EXPECT_NE(bunny->collision.mesh_path.find("stanford-bunny-1k-quadric.obj"), std::string::npos);
  EXPECT_DOUBLE_EQ(bunny->collision.scale.x(), 0.8);
  EXPECT_DOUBLE_EQ(*bunny->mass_kg, 0.2);
  EXPECT_EQ(bunny->spawn_at_start.size(), 1u);
  EXPECT_EQ(bunny->max_instances, 20);
  EXPECT_EQ(scene.channels.world_state, "ARPHYS_WORLD_STATE");
  EXPECT_NEAR(scene.gravity_m_s2.z(), -9.81, 0);
}

TEST(SceneConfig, SpoonTeacupLoads) {
  const SceneConfig scene = load_scene(kConfigs + "scenes/spoon_teacup.yaml");
  EXPECT_EQ(scene.name, "spoon_teacup");
  EXPECT_EQ(scene.find_object("table")->collision.type, ShapeType::kPlane);
  EXPECT_EQ(scene.find_object("table")->render.type, ShapeType::kBox);
  EXPECT_EQ(scene.find_object("teacup")->motion, Motion::kStatic);
  EXPECT_EQ(scene.find_object("spoon")->markers.size(), 1u);
}

// Writes a scene file next to the real models, with `object` as the only object
// besides a valid table, and returns the ConfigError message from loading it.
class BadScene : public ::testing::Test {
 protected:
  std::string load_error(const std::string& objects_yaml, const std::string& extra_top = "") {
    path_ = ::testing::TempDir() + "bad_scene_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml";
    std::ofstream out(path_);
    out << "name: bad\ncamera: " << kConfigs << "cameras/synthetic_640x480.yaml\n" << extra_top
        << "objects:\n"
           "  - id: table\n"
           "    role: real\n"
           "    motion: static\n"
           "    collision: {shape: plane}\n"
           "    markers:\n"
           "      - {family: tag36h11, id: 0, size_m: 0.05, pose: {position_m: [0, 0, 0], orientation_wxyz: [1, 0, 0, 0]}}\n"
        << objects_yaml;
    out.close();
    try {
      load_scene(path_);
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), path_);
      return e.what();
    }
    ADD_FAILURE() << "scene loaded without error";
    return "";
  }
  std::string path_;
};

TEST_F(BadScene, MissingMeshNamesFileKeyAndPath) {
  const std::string message = load_error(
      "  - id: cup\n    role: virtual\n    motion: static\n"
      "    collision: {shape: mesh, mesh: no_such_cup.obj}\n");
  EXPECT_NE(message.find(path_), std::string::npos) << message;
  EXPECT_NE(message.find("objects[1].collision.mesh"), std::string::npos) << message;
  EXPECT_NE(message.find("no_such_cup.obj"), std::string::npos) << message;
  EXPECT_NE(message.find("not found"), std::string::npos) << message;
}

TEST_F(BadScene, NegativeSizeNamesTheComponentAndValue) {
  const std::string message = load_error(
      "  - id: box\n    role: virtual\n    motion: dynamic\n"
      "    collision: {shape: box, size_m: [0.1, -0.2, 0.1]}\n");
  EXPECT_NE(message.find("objects[1].collision.size_m[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("got -0.2"), std::string::npos) << message;
  EXPECT_NE(message.find("expected a positive length in metres"), std::string::npos) << message;
  EXPECT_NE(message.find(":13:"), std::string::npos) << "line number of the bad value: " << message;
}

TEST_F(BadScene, UnknownRoleListsTheChoices) {
  const std::string message = load_error(
      "  - id: box\n    role: imaginary\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n");
  EXPECT_NE(message.find("objects[1].role"), std::string::npos) << message;
  EXPECT_NE(message.find("'imaginary'"), std::string::npos) << message;
  EXPECT_NE(message.find("expected 'real' or 'virtual'"), std::string::npos) << message;
}

TEST_F(BadScene, DuplicateMarkerAcrossObjectsNamesBothPlaces) {
  const std::string message = load_error(
      "  - id: box\n    role: real\n    motion: kinematic\n    collision: {shape: box, size_m: [0.1, 0.1, 0.1]}\n"
      "    markers:\n"
      "      - {family: tag36h11, id: 0, size_m: 0.05, pose: {position_m: [0, 0, 0.05], orientation_wxyz: [1, 0, 0, 0]}}\n");
  EXPECT_NE(message.find("objects[1].markers[0].id"), std::string::npos) << message;
  EXPECT_NE(message.find("duplicate marker tag36h11 id 0"), std::string::npos) << message;
  EXPECT_NE(message.find("objects[0].markers[0]"), std::string::npos) << message;
}

TEST_F(BadScene, NonUnitQuaternionGivesItsNorm) {
  const std::string message = load_error(
      "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n"
      "    pose: {position_m: [0, 0, 1], orientation_wxyz: [1, 0.1, 0, 0]}\n");
  EXPECT_NE(message.find("objects[1].pose.orientation_wxyz"), std::string::npos) << message;
  EXPECT_NE(message.find("norm 1.00499"), std::string::npos) << message;
  EXPECT_NE(message.find("expected a unit quaternion"), std::string::npos) << message;
}

TEST_F(BadScene, UnknownKeyIsATypoNotADefault) {
  const std::string message = load_error(
      "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n"
      "    restitutoin: 0.5\n");
  EXPECT_NE(message.find("objects[1].restitutoin"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown key"), std::string::npos) << message;
}

TEST_F(BadScene, RealDynamicObjectIsRejected) {
  const std::string message = load_error(
      "  - id: hand\n    role: real\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n");
  EXPECT_NE(message.find("objects[1].motion"), std::string::npos) << message;
}

TEST_F(BadScene, RestitutionOutOfRange) {
  const std::string message = load_error(
      "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n"
      "    restitution: 1.5\n");
  EXPECT_NE(message.find("objects[1].restitution: got 1.5, expected a coefficient of restitution in [0, 1]"),
            std::string::npos)
      << message;
}

TEST_F(BadScene, UnknownShapeAndNonNumber) {
  EXPECT_NE(load_error("  - id: b\n    role: virtual\n    motion: dynamic\n    collision: {shape: cylinder}\n")
                .find("expected one of: plane, box, sphere, mesh"),
            std::string::npos);
  EXPECT_NE(load_error("  - id: b\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: big}\n")
                .find("objects[1].collision.radius_m: got 'big'"),
            std::string::npos);
}

TEST_F(BadScene, DuplicateObjectId) {
  const std::string message =
      load_error("  - id: table\n    role: virtual\n    motion: static\n    collision: {shape: sphere, radius_m: 0.1}\n");
  EXPECT_NE(message.find("duplicate object id 'table'"), std::string::npos) << message;
}

TEST_F(BadScene, TrajectoryTimesMustIncrease) {
  const std::string error = load_error(
      "  - id: pusher\n    role: real\n    motion: kinematic\n    collision: {shape: box, size_m: [0.2, 0.2, 0.2]}\n"
      "    trajectory:\n"
      "      - {t_s: 0.0, pose: {position_m: [0, 0, 0.1], orientation_wxyz: [1, 0, 0, 0]}}\n"
      "      - {t_s: 0.0, pose: {position_m: [1, 0, 0.1], orientation_wxyz: [1, 0, 0, 0]}}\n");
  EXPECT_NE(error.find("objects[1].trajectory[1].t_s"), std::string::npos) << error;
  EXPECT_NE(error.find("expected a time after the previous one"), std::string::npos) << error;
}

TEST_F(BadScene, VelocityOnlyForDynamicAndTrajectoryOnlyForKinematic) {
  std::string error = load_error(
      "  - id: pusher\n    role: real\n    motion: kinematic\n    collision: {shape: box, size_m: [0.2, 0.2, 0.2]}\n"
      "    velocity_m_s: [1, 0, 0]\n");
  EXPECT_NE(error.find("objects[1].velocity_m_s"), std::string::npos) << error;
  error = load_error(
      "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n"
      "    trajectory: [{t_s: 0, pose: {position_m: [0, 0, 0.1], orientation_wxyz: [1, 0, 0, 0]}}]\n");
  EXPECT_NE(error.find("only a kinematic object follows a trajectory"), std::string::npos) << error;
}

TEST_F(BadScene, SolverAndTrackingPolicyAreChecked) {
  const std::string ball = "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n";
  std::string error = load_error(ball, "physics: {solver: lcp}\n");
  EXPECT_NE(error.find("physics.solver"), std::string::npos) << error;
  EXPECT_NE(error.find("expected 'exact' or 'iterative'"), std::string::npos) << error;
  error = load_error(ball, "physics: {tracking_policy: guess}\n");
  EXPECT_NE(error.find("expected 'delay' or 'extrapolate'"), std::string::npos) << error;
}

TEST_F(BadScene, ContactGapAndOverlapToleranceArePositiveLengthsBelowATenthOfAMillimetre) {
  const std::string ball = "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n";
  std::string error = load_error(ball, "physics: {contact_gap_m: 0.001}\n");
  EXPECT_NE(error.find("physics.contact_gap_m: got 0.001, expected a positive length below 1e-4 m"), std::string::npos) << error;
  error = load_error(ball, "physics: {overlap_tolerance_m: -1e-6}\n");
  EXPECT_NE(error.find("physics.overlap_tolerance_m"), std::string::npos) << error;
  error = load_error(ball, "physics: {overlap_tolerance_m: tiny}\n");
  EXPECT_NE(error.find("physics.overlap_tolerance_m"), std::string::npos) << error;
}

TEST_F(BadScene, SleepingTimesAndSpeedsAreChecked) {
  const std::string ball = "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n";
  std::string error = load_error(ball, "physics: {sleep_after_s: -1}\n");
  EXPECT_NE(error.find("physics.sleep_after_s: got -1, expected 0 (never sleep) to 3600 s"), std::string::npos) << error;
  error = load_error(ball, "physics: {sleep_after_s: soon}\n");
  EXPECT_NE(error.find("physics.sleep_after_s"), std::string::npos) << error;
  error = load_error(ball, "physics: {sleep_speed_m_s: 0}\n");
  EXPECT_NE(error.find("physics.sleep_speed_m_s"), std::string::npos) << error;
  error = load_error(ball, "physics: {sleep_speed_m_s: 3}\n");
  EXPECT_NE(error.find("expected a speed of at most 1 m/s"), std::string::npos) << error;
}

// Every other refusal of the loader, one bad key each: the message names the key (its
// path in the file) and what was expected there.
TEST_F(BadScene, EveryRefusalNamesTheKeyAndWhatWasExpected) {
  const std::string ball = "  - id: ball\n    role: virtual\n    motion: dynamic\n    collision: {shape: sphere, radius_m: 0.1}\n";
  const std::string pose = "{position_m: [0, 0, 0.5], orientation_wxyz: [1, 0, 0, 0]}";
  struct Case {
    std::string objects, top, expected;
  };
  const std::vector<Case> cases{
      {"  - id: b\n    role: virtual\n    motion: floating\n    collision: {shape: sphere, radius_m: 0.1}\n", "",
       "objects[1].motion: got 'floating', expected 'static', 'kinematic' or 'dynamic'"},
      {"  - id: b\n    role: virtual\n    motion: dynamic\n    collision: {shape: plane}\n", "",
       "objects[1].collision.shape: a plane cannot be dynamic (it has no mass), expected box, sphere, mesh or convex_set"},
      {"  - id: b\n    role: virtual\n    motion: dynamic\n    collision: {shape: convex_set, scale: 0.8}\n", "",
       "objects[1].collision.pieces"},
      {"  - id: b\n    role: virtual\n    motion: dynamic\n    collision: {shape: convex_set, pieces: nowhere.obj}\n", "",
       "objects[1].collision.pieces: convex-piece file 'nowhere.obj' not found"},
      {"  - id: b\n    role: virtual\n    motion: dynamic\n    collision: {shape: box, size_m: [1, 1, 1], pieces: a.obj}\n",
       "", "objects[1].collision.pieces: 'pieces' is a key of convex_set shapes, not of a box"},
      {ball + "    mass_kg: 1\n    density_kg_m3: 1000\n", "",
       "objects[1].density_kg_m3: given together with mass_kg, expected at most one of them"},
      {ball + "    density_kg_m3: -5\n", "", "objects[1].density_kg_m3: got -5, expected a positive density in kg/m^3"},
      {ball + "    friction: -0.1\n", "", "objects[1].friction: got -0.1, expected a Coulomb friction coefficient >= 0"},
      {"  - id: pusher\n    role: real\n    motion: kinematic\n    collision: {shape: box, size_m: [0.2, 0.2, 0.2]}\n"
       "    trajectory: []\n",
       "", "objects[1].trajectory: got an empty list, expected a non-empty list of {t_s, pose}"},
      {ball + "    markers:\n      - {family: tag36h11, id: 5, size_m: 0.05, pose: " + pose + "}\n", "",
       "objects[1].markers: a virtual object carries no markers, expected markers only on real objects"},
      {"  - id: pusher\n    role: real\n    motion: kinematic\n    collision: {shape: box, size_m: [0.2, 0.2, 0.2]}\n"
       "    spawn: {max_instances: 2}\n",
       "", "objects[1].spawn: only virtual dynamic objects can be spawned"},
      {ball + "    spawn: {max_instances: 0}\n", "", "objects[1].spawn.max_instances: got 0, expected 1 to 10000"},
      {ball + "    spawn:\n      max_instances: 1\n      at_start:\n        - {pose: " + pose + "}\n        - {pose: " + pose +
           "}\n",
       "", "objects[1].spawn.at_start: 2 instances, more than max_instances = 1"},
      {ball, "channels: {world_stat: MY_WORLD}\n", "channels.world_stat: unknown key"},
      {ball, "physics: {solver_iterations: 0}\n", "physics.solver_iterations: got 0, expected 1 to 100000 sweeps"},
      {ball, "physics: {time_step_s: 0.5}\n", "physics.time_step_s: got 0.5, expected a time step of at most 0.1 s"},
  };
  for (const Case& c : cases) {
    const std::string message = load_error(c.objects, c.top);
    EXPECT_NE(message.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << message;
  }
}

// What those keys accept: channel names, and a dynamic object's starting velocities.
TEST(SceneConfig, ChannelsAndStartingVelocitiesAreReadWhenGiven) {
  const std::string path = ::testing::TempDir() + "channels_scene.yaml";
  std::ofstream(path) << "name: channels\nchannels: {world_state: MY_WORLD, sim_command: MY_COMMANDS}\nobjects:\n"
                         "  - {id: floor, role: real, motion: static, collision: {shape: plane}}\n"
                         "  - {id: ball, role: virtual, motion: dynamic, collision: {shape: sphere, radius_m: 0.1},\n"
                         "     velocity_m_s: [1, 2, 3], angular_velocity_rad_s: [0, 0, 5]}\n";
  const SceneConfig scene = load_scene(path);
  EXPECT_EQ(scene.channels.world_state, "MY_WORLD");
  EXPECT_EQ(scene.channels.sim_command, "MY_COMMANDS");
  EXPECT_EQ(scene.channels.object_poses, "ARPHYS_OBJECT_POSES");  // the others keep their defaults
  const ObjectConfig* ball = scene.find_object("ball");
  ASSERT_NE(ball, nullptr);
  EXPECT_EQ(ball->v_WO_m_s, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(ball->w_WO_rad_s, Eigen::Vector3d(0, 0, 5));
}

TEST(SceneConfig, SleepingIsOffUnlessAsked) {
  EXPECT_EQ(load_scene(kConfigs + "scenes/drop100.yaml").sleep_after_s, 0.0);
  const std::string path = ::testing::TempDir() + "sleep_scene.yaml";
  std::ofstream(path) << "name: sleepy\nphysics: {sleep_after_s: 0.5, sleep_speed_m_s: 0.02}\nobjects:\n"
                         "  - {id: floor, role: real, motion: static, collision: {shape: plane}}\n";
  const SceneConfig scene = load_scene(path);
  EXPECT_DOUBLE_EQ(scene.sleep_after_s, 0.5);
  EXPECT_DOUBLE_EQ(scene.sleep_speed_m_s, 0.02);
}

TEST(SceneConfig, ContactGapAndOverlapToleranceAreReadWhenGiven) {
  EXPECT_FALSE(load_scene(kConfigs + "scenes/drop100.yaml").contact_gap_m);  // the world's defaults
  const std::string path = ::testing::TempDir() + "gap_scene.yaml";
  std::ofstream(path) << "name: gap\nphysics: {contact_gap_m: 1.0e-5, overlap_tolerance_m: 2.0e-5}\nobjects:\n"
                         "  - {id: floor, role: real, motion: static, collision: {shape: plane}}\n";
  const SceneConfig scene = load_scene(path);
  ASSERT_TRUE(scene.contact_gap_m && scene.overlap_tolerance_m);
  EXPECT_DOUBLE_EQ(*scene.contact_gap_m, 1e-5);
  EXPECT_DOUBLE_EQ(*scene.overlap_tolerance_m, 2e-5);
}

TEST(SceneConfigFile, MissingAndMalformedFiles) {
  EXPECT_THROW(load_scene("/no/such/scene.yaml"), ConfigError);
  const std::string path = ::testing::TempDir() + "malformed.yaml";
  std::ofstream(path) << "name: [unclosed\nobjects: {\n";
  try {
    load_scene(path);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not valid YAML"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arphys::config
