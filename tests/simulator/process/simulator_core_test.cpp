#include "simulator/process/simulator_core.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "simulator/collision/discrete_query.hpp"

namespace arphys::sim {
namespace {

const std::string kScenes = std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/";
constexpr int64_t kStart = 1'700'000'000'000'000;  // a capture utime

TrackingFrame frame(int64_t utime, int64_t seq, const std::string& id, const Eigen::Vector3d& p) {
  TrackingFrame f;
  f.capture_utime = utime;
  f.seq = seq;
  TrackedObject o;
  o.object_id = id;
  o.X_WO = geometry::translation_pose(p);
  f.objects.push_back(o);
  return f;
}

// A body followed along x while the core steps: where it is, and the fastest it moved in a step.
struct XWatch {
  double x_m = 0, fastest_m_s = 0;
};

// Steps the core one time step at a time up to simulation time t_s, watching `body`.
void step_watching_x(SimulatorCore& core, int body, double t_s, XWatch& watch) {
  const double dt = core.time_step_s();
  while (core.sim_time_s() + dt <= t_s + 1e-12) {
    core.advance_to(core.sim_time_s() + dt);
    const double x = core.world().body_state(body).X_WB.translation().x();
    watch.fastest_m_s = std::max(watch.fastest_m_s, (x - watch.x_m) / dt);
    watch.x_m = x;
  }
}

TEST(SimulatorCore, FramesOutOfOrderDuplicatedOrForUnknownObjectsAreRefusedWithReasons) {
  SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), {});
  EXPECT_EQ(core.on_tracking(frame(kStart, 1, "box", {0.25, 0, 0.075})), 1);
  EXPECT_EQ(core.on_tracking(frame(kStart, 1, "box", {0.25, 0, 0.075})), 0);
  EXPECT_EQ(core.rejections().at("duplicate tracking frame"), 1);
  EXPECT_EQ(core.on_tracking(frame(kStart - 1000, 2, "box", {0.25, 0, 0.075})), 0);
  EXPECT_EQ(core.rejections().at("out-of-order tracking frame"), 1);
  EXPECT_EQ(core.on_tracking(frame(kStart + 33'333, 3, "ghost", {0, 0, 0})), 0);
  EXPECT_EQ(core.rejections().at("unknown object 'ghost'"), 1);
  // The table fixes the world: reported by the tracker, not driven by it, and not an error.
  EXPECT_EQ(core.on_tracking(frame(kStart + 66'666, 4, "table", {0, 0, 0})), 0);
  TrackingFrame nan = frame(kStart + 99'999, 5, "box", {0.25, 0, 0.075});
  nan.objects[0].X_WO.translation().x() = std::nan("");
  EXPECT_EQ(core.on_tracking(nan), 0);
  EXPECT_EQ(core.rejections().at("non-finite pose of 'box'"), 1);
  EXPECT_EQ(core.rejected_total(), 4);
}

TEST(SimulatorCore, TrackedBoxFollowsOneFrameLateAndIsHeldWhenLost) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  scene.time_step_s = 0.01;  // the figures below are to within one 10 ms step
  SimulatorCore core(scene, {});
  const int box = core.world().find("box");
  ASSERT_GE(box, 0);
  for (int k = 0; k <= 30; ++k)  // 1 s at 30 Hz, moving +x at 0.3 m/s
    core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
  core.advance_to(core.sim_time_of(kStart + 30 * 33'333));
  EXPECT_NEAR(core.added_latency_s("box"), 1.0 / 30, 2e-3);
  // One frame behind the last measurement (0.55 m), along the path (within a 10 ms step).
  EXPECT_NEAR(core.world().body_state(box).X_WB.translation().x(), 0.54, 4e-3);
  EXPECT_TRUE(core.lost_objects().empty());
  // No more frames: after the stale timeout the box is held where it is.
  core.advance_to(core.sim_time_s() + 1.0);
  const double held = core.world().body_state(box).X_WB.translation().x();
  core.advance_to(core.sim_time_s() + 1.0);
  EXPECT_EQ(core.world().body_state(box).X_WB.translation().x(), held);
  EXPECT_EQ(core.lost_objects(), std::vector<std::string>{"box"});
}

// The tracker's LOST status holds the box where it is at once (not after the stale
// timeout), and is not an error; a pose not in the world frame (the table unseen) is
// refused with its reason. The next pose re-acquires the box, which moves there no faster
// than the driver's speed limit.
TEST(SimulatorCore, ALostTrackHoldsTheBoxAtOnceAndTheNextPoseReacquiresIt) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  scene.time_step_s = 0.01;
  SimulatorCore core(scene, {});
  const int box = core.world().find("box");
  int k = 0;
  for (; k <= 15; ++k) core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
  core.advance_to(core.sim_time_of(kStart + 15 * 33'333));
  TrackingFrame lost = frame(kStart + 16 * 33'333, 17, "box", {0, 0, 0});
  lost.objects[0].lost = true;
  EXPECT_EQ(core.on_tracking(lost), 0);
  TrackingFrame unframed = frame(kStart + 17 * 33'333, 18, "box", {0.9, 0, 0.0755});
  unframed.objects[0].world_valid = false;
  EXPECT_EQ(core.on_tracking(unframed), 0);
  EXPECT_EQ(core.rejections().at("pose of 'box' not in the world frame"), 1);
  EXPECT_EQ(core.rejected_total(), 1);  // the LOST status was not one
  core.advance_to(core.sim_time_of(kStart + 17 * 33'333) + 0.2);  // well within the stale timeout
  // Held where it was last seen (0.40 m; one frame late, it got there as the LOST frame came).
  const double held_x = core.world().body_state(box).X_WB.translation().x();
  EXPECT_NEAR(held_x, 0.40, 1e-6);
  core.advance_to(core.sim_time_s() + 0.1);
  EXPECT_EQ(core.world().body_state(box).X_WB.translation().x(), held_x);
  // Seen again 10 cm further: it moves there, at most 1.5 m/s (the driver's limit).
  const double t = core.sim_time_s();
  core.on_tracking(frame(kStart + 30 * 33'333, 31, "box", {held_x + 0.1, 0, 0.0755}));
  XWatch watch{held_x};
  step_watching_x(core, box, t + 0.5, watch);
  EXPECT_NEAR(watch.x_m, held_x + 0.1, 1e-6);
  EXPECT_LE(watch.fastest_m_s, 1.5 + 1e-6);
}

// Pause (the renderer's p key) freezes the virtual world and the tracked box where they
// are; resume goes on from there. The time paused is not simulated afterwards (before,
// the world fast-forwarded through it at the next step, a tracked box pushing through
// everything it had been moved across meanwhile), and the box, moved while paused, is
// re-acquired as after a lost track.
TEST(SimulatorCore, PauseFreezesTheWorldAndResumeGoesOnFromWhereItWas) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  scene.time_step_s = 0.01;
  SimulatorCore core(scene, {});
  const int box = core.world().find("box");
  int seq = 0;
  const auto feed = [&](double from_s, double to_s, double box_x_at_0, double speed_m_s) {
    for (double t = from_s; t <= to_s + 1e-9; t += 1.0 / 30) {
      const int64_t utime = kStart + std::llround(t * 1e6);
      core.on_tracking(frame(utime, ++seq, "box", {box_x_at_0 + speed_m_s * t, 0, 0.0755}));
      core.advance_to(core.sim_time_of(utime));
    }
  };
  feed(0.0, 0.5, 0.25, 0.0);
  SpawnRequest command;
  command.sender = "renderer";
  command.seq = 1;
  command.kind = SpawnRequest::Kind::kPause;
  ASSERT_TRUE(core.on_command(command));
  EXPECT_TRUE(core.paused());
  const double paused_at_s = core.sim_time_s();
  const std::vector<dynamics::RigidBody> frozen = core.world().body_copies();
  feed(0.5 + 1.0 / 30, 2.5, 0.25 - 0.1 * 0.5, 0.1);  // 2 s paused; the box moved 20 cm meanwhile
  EXPECT_EQ(core.sim_time_s(), paused_at_s);
  for (std::size_t i = 0; i < frozen.size(); ++i)
    EXPECT_TRUE(core.world().body_state(i).X_WB.matrix() == frozen[i].X_WB.matrix()) << frozen[i].id;
  command.seq = 2;
  command.kind = SpawnRequest::Kind::kResume;
  ASSERT_TRUE(core.on_command(command));
  EXPECT_FALSE(core.paused());
  XWatch watch{core.world().body_state(box).X_WB.translation().x()};
  for (double t = 2.5 + 1.0 / 30; t <= 3.7 + 1e-9; t += 1.0 / 30) {
    const int64_t utime = kStart + std::llround(t * 1e6);
    core.on_tracking(frame(utime, ++seq, "box", {0.45, 0, 0.0755}));  // it stays where it was moved to
    step_watching_x(core, box, core.sim_time_of(utime), watch);
  }
  EXPECT_NEAR(core.sim_time_s(), paused_at_s + 1.2, 0.02) << "1.2 s since the resume, not 3.2";
  // Re-acquired as a lost track is, not swept in one step: at twice the speed the box made
  // over the 2.03 s since its last capture before the pause (0.2 m), so about a second.
  EXPECT_LE(watch.fastest_m_s, 2 * 0.2 / (2.5 + 1.0 / 30 - 0.5) + 1e-6);
  EXPECT_NEAR(watch.x_m, 0.45, 1e-6);
  EXPECT_EQ(core.dropped_time_s(), 0.0) << "a pause is not time given up to keep up";
}

TEST(SimulatorCore, ExtrapolatePolicyAddsNoLatency) {
  CoreOptions options;
  options.policy = TrackingPolicy::kExtrapolate;
  SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), options);
  const int box = core.world().find("box");
  for (int k = 0; k <= 30; ++k) core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
  core.advance_to(core.sim_time_of(kStart + 30 * 33'333));
  EXPECT_EQ(core.added_latency_s("box"), 0.0);
  EXPECT_NEAR(core.world().body_state(box).X_WB.translation().x(), 0.55, 3e-3);
}

// A live simulator that cannot keep up gives simulation time up (arphys-simulator
// --max-lag-s): captures map that much earlier, and the tracked box covers it in its next
// step, then follows its frames one frame late as before.
TEST(SimulatorCore, GivenUpTimeMovesCapturesEarlierAndTheTrackedBoxCoversIt) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  scene.time_step_s = 0.01;
  SimulatorCore core(scene, {});
  const int box = core.world().find("box");
  const auto box_x = [&] { return core.world().body_state(box).X_WB.translation().x(); };
  for (int k = 0; k <= 30; ++k)  // 1 s at 30 Hz, moving +x at 0.3 m/s
    core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
  const int64_t newest = kStart + 30 * 33'333;
  core.advance_to(core.sim_time_of(newest));
  const double mapped_before_s = core.sim_time_of(newest), x_before = box_x();

  core.drop_time(0.005);
  EXPECT_NEAR(core.sim_time_of(newest), mapped_before_s - 0.005, 1e-9);
  EXPECT_DOUBLE_EQ(core.dropped_time_s(), 0.005);
  EXPECT_EQ(core.advance_to(core.sim_time_s() + 0.01), 1);
  // 15 ms of its 0.3 m/s motion in one 10 ms step (held at its pose, it would move 3 mm
  // and then have to catch up).
  EXPECT_NEAR(box_x() - x_before, 0.0045, 2e-4);
  EXPECT_TRUE(core.lost_objects().empty());
  for (int k = 31; k <= 45; ++k) {
    core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
    core.advance_to(core.sim_time_of(kStart + k * 33'333));
  }
  EXPECT_NEAR(box_x(), 0.69, 4e-3);  // one frame behind the last measurement (0.70)
  for (const double bad : {0.0, -0.1, std::nan(""), HUGE_VAL}) {
    try {
      core.drop_time(bad);
      ADD_FAILURE() << "drop_time(" << bad << ") accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("dropped_s"), std::string::npos) << e.what();
    }
  }
  EXPECT_DOUBLE_EQ(core.dropped_time_s(), 0.005);
}

// The same under the extrapolate policy: the box covers the time given up along its
// measured twist and then stays on its measurements, with no latency.
TEST(SimulatorCore, GivenUpTimeLeavesAnExtrapolatedBoxOnItsMeasurements) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  scene.time_step_s = 0.01;
  CoreOptions options;
  options.policy = TrackingPolicy::kExtrapolate;
  SimulatorCore core(scene, options);
  const int box = core.world().find("box");
  const auto box_x = [&] { return core.world().body_state(box).X_WB.translation().x(); };
  for (int k = 0; k <= 30; ++k) {
    core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
    core.advance_to(core.sim_time_of(kStart + k * 33'333));
  }
  const double x_before = box_x();
  core.drop_time(0.005);
  EXPECT_EQ(core.advance_to(core.sim_time_s() + 0.01), 1);
  EXPECT_NEAR(box_x() - x_before, 0.0045, 3e-4);
  for (int k = 31; k <= 45; ++k) {
    core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 + 0.01 * k, 0, 0.0755}));
    core.advance_to(core.sim_time_of(kStart + k * 33'333));
  }
  EXPECT_NEAR(box_x(), 0.70, 3e-3);
}

TEST(SimulatorCore, SpawnRequestsBeyondLimitsAreRefused) {
  SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), {});
  const std::size_t before = core.world().body_count();
  SpawnRequest spawn;
  spawn.sender = "test";
  spawn.model = "bunny";
  spawn.X_WB = geometry::translation_pose({0, 0, 0.3});
  spawn.seq = 1;
  EXPECT_TRUE(core.on_command(spawn));
  EXPECT_EQ(core.world().body_count(), before + 1);
  EXPECT_FALSE(core.on_command(spawn));  // the same seq again: a repeat
  spawn.seq = 2;
  spawn.v_WB_m_s = Eigen::Vector3d(100, 0, 0);
  EXPECT_FALSE(core.on_command(spawn));
  spawn.seq = 3;
  spawn.v_WB_m_s.setZero();
  spawn.X_WB = geometry::translation_pose({50, 0, 0.3});
  EXPECT_FALSE(core.on_command(spawn));
  spawn.seq = 4;
  spawn.model = "table";
  spawn.X_WB = geometry::translation_pose({0, 0, 0.3});
  EXPECT_FALSE(core.on_command(spawn));
  spawn.model = "bunny";
  for (int k = 0; k < 40; ++k) {
    spawn.seq = 10 + k;
    spawn.X_WB = geometry::translation_pose({-0.5 + 0.2 * (k % 6), -0.35 + 0.2 * ((k / 6) % 4), 0.5 + 0.25 * (k / 24)});
    core.on_command(spawn);
  }
  int bunnies = 0;
  for (const auto& body : core.world().body_copies()) bunnies += body.model == "bunny";
  EXPECT_EQ(bunnies, 20);  // max_instances
  EXPECT_GE(core.rejected_total(), 4 + 20);
  SpawnRequest remove;
  remove.sender = "test";
  remove.seq = 100;
  remove.kind = SpawnRequest::Kind::kRemove;
  remove.body_id = "box";  // a real body
  EXPECT_FALSE(core.on_command(remove));
  remove.seq = 101;
  remove.body_id = "bunny#0";
  EXPECT_TRUE(core.on_command(remove));
}

// Two bunnies thrown into the same place: the second would start inside the first and
// is refused with a reason (a flood of such spawns buried the solver before).
TEST(SimulatorCore, SpawnIntoAnotherBodyIsRefused) {
  SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), {});
  SpawnRequest spawn;
  spawn.sender = "test";
  spawn.kind = SpawnRequest::Kind::kSpawn;
  spawn.model = "bunny";
  spawn.X_WB = geometry::make_pose({0.1, 0.2, 0.3}, {0.7071067811865476, 0.7071067811865476, 0, 0});
  spawn.seq = 1;
  EXPECT_TRUE(core.on_command(spawn));
  spawn.seq = 2;
  EXPECT_FALSE(core.on_command(spawn));
  EXPECT_EQ(core.rejections().count("spawn of 'bunny': would overlap 'bunny#1'"), 1u) << core.last_rejection();
  spawn.seq = 3;
  spawn.X_WB.translation().x() = -0.2;  // clear of it
  EXPECT_TRUE(core.on_command(spawn));
}

// A restarted simulator resumes the virtual bodies its previous run left: the scene's
// own bunny continues from its saved state, spawned ones come back under their ids,
// the next spawn continues the numbering, and what cannot come back says why.
TEST(SimulatorCore, RestartResumesVirtualBodiesAndListsWhatItCannot) {
  const config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  SimulatorCore before(scene, {});
  SpawnRequest spawn;
  spawn.sender = "test";
  spawn.model = "bunny";
  for (int k = 0; k < 3; ++k) {
    spawn.seq = k + 1;
    spawn.X_WB = geometry::make_pose({-0.3 + 0.25 * k, 0.1, 0.3}, {0.7071067811865476, 0.7071067811865476, 0, 0});
    spawn.v_WB_m_s = Eigen::Vector3d(0, 0.2, 0);
    ASSERT_TRUE(before.on_command(spawn)) << before.last_rejection();
  }
  before.advance_to(0.2);
  std::vector<RecoveredBody> saved;
  for (const auto& body : before.world().body_copies()) {
    if (body.real || !body.is_dynamic()) continue;
    saved.push_back({body.id, body.model, body.X_WB, body.origin_velocity(), body.w_WB_rad_s});
  }
  ASSERT_EQ(saved.size(), 4u);  // bunny#0 from the scene, bunny#1..3 spawned
  RecoveredBody unknown = saved.back();
  unknown.body_id = "teapot#0";
  unknown.model = "teapot";
  RecoveredBody twin = saved.back();  // on top of bunny#3
  twin.body_id = "bunny#9";
  // Touching bunny#3 as bunnies at rest do: 0.1 mm into it along x (where a shift along x
  // stops their meshes intersecting, found by bisection). A spawn there would be refused;
  // a resumed body was there in the world before the restart and comes back.
  const dynamics::RigidBody& third = before.world().body_copy(before.world().find("bunny#3"));
  const collision::CollisionMesh& mesh = *third.shape.triangles();
  const auto shifted = [&](double x_m) {
    geometry::Pose X = third.X_WB;
    X.translation().x() += x_m;
    return X;
  };
  double inside_m = 0, clear_m = 0.5;
  ASSERT_FALSE(collision::intersects(mesh, third.X_WB, mesh, shifted(clear_m)));
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (inside_m + clear_m);
    (collision::intersects(mesh, third.X_WB, mesh, shifted(mid)) ? inside_m : clear_m) = mid;
  }
  RecoveredBody neighbour = saved.back();
  neighbour.body_id = "bunny#8";
  neighbour.X_WB = shifted(clear_m - 1e-4);
  ASSERT_TRUE(collision::intersects(mesh, third.X_WB, mesh, neighbour.X_WB));
  std::vector<RecoveredBody> file = saved;
  file.push_back(unknown);
  file.push_back(twin);
  file.push_back(neighbour);

  SimulatorCore after(scene, {});
  const RecoveryReport report = after.recover(file);
  EXPECT_EQ(report.recovered, 5);
  ASSERT_EQ(report.lost.size(), 2u);
  EXPECT_EQ(report.lost[0], "teapot#0: model 'teapot' is not in the scene");
  EXPECT_EQ(report.lost[1], "bunny#9: would overlap 'bunny#3' (at its pose)");
  EXPECT_GE(after.world().find("bunny#8"), 0);
  for (const RecoveredBody& b : saved) {
    const int index = after.world().find(b.body_id);
    ASSERT_GE(index, 0) << b.body_id;
    const auto& body = after.world().body_copy(index);
    EXPECT_LT((body.X_WB.matrix() - b.X_WB.matrix()).norm(), 1e-12) << b.body_id;
    EXPECT_LT((body.origin_velocity() - b.v_WB_m_s).norm(), 1e-12) << b.body_id;
  }
  spawn.seq = 1;
  spawn.X_WB = geometry::make_pose({0.4, -0.3, 0.3}, {0.7071067811865476, 0.7071067811865476, 0, 0});
  ASSERT_TRUE(after.on_command(spawn)) << after.last_rejection();
  EXPECT_GE(after.world().find("bunny#9"), 0);  // after the highest resumed id, bunny#8
}

// A bunny thrown past the table falls out of the world: it is removed (so it no longer
// holds an instance) and listed, instead of falling forever.
// The tracked box goes back where it was, and the first tracked pose after the restart
// moves it on within the tracking speed limit: left at its scene pose it jumped to the
// tracked pose, into the bunnies it had been pushing.
TEST(SimulatorCore, RestartPutsTheTrackedBoxBackAndMovesItOnSmoothly) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  SimulatorCore core(scene, {});
  const Eigen::Vector3d saved_at(-0.2, 0.1, 0.0755);
  RecoveredBody box{"box", "box", geometry::translation_pose(saved_at)};
  core.recover({box});
  const int index = core.world().find("box");
  EXPECT_LT((core.world().body_state(index).X_WB.translation() - saved_at).norm(), 1e-12);
  core.on_tracking(frame(kStart, 1, "box", saved_at + Eigen::Vector3d(0.15, 0, 0)));
  const Eigen::Vector3d before = core.world().body_state(index).X_WB.translation();
  core.advance_to(core.time_step_s());
  const double moved_m = (core.world().body_state(index).X_WB.translation() - before).norm();
  EXPECT_GT(moved_m, 0.0);
  EXPECT_LE(moved_m, 1.5 * core.time_step_s() + 1e-9);  // the tracking driver's 1.5 m/s
}

TEST(SimulatorCore, BodyLeavingTheWorldIsRemovedAndListed) {
  SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), {});
  SpawnRequest spawn;
  spawn.sender = "test";
  spawn.model = "bunny";
  spawn.seq = 1;
  spawn.X_WB = geometry::translation_pose({1.0, 0, 0.3});  // beside the table
  spawn.v_WB_m_s = Eigen::Vector3d(0, 0, -15);
  ASSERT_TRUE(core.on_command(spawn));
  ASSERT_GE(core.world().find("bunny#1"), 0);
  core.advance_to(0.5);
  ASSERT_GE(core.world().find("bunny#1"), 0);  // 8.7 m down: still inside
  core.advance_to(1.0);
  EXPECT_LT(core.world().find("bunny#1"), 0);
  EXPECT_EQ(core.bodies_left_world(), 1);
  EXPECT_EQ(core.last_body_left_world(), "bunny#1");
  EXPECT_GE(core.world().find("bunny#0"), 0);  // the one on the table stays
}

// Hostile traffic with ever-new object ids and senders must not grow the process's
// tables: the refusals are all counted, in a bounded table.
TEST(SimulatorCore, RefusalTablesStayBoundedUnderRandomNames) {
  SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), {});
  for (int k = 0; k < 5000; ++k) {
    core.on_tracking(frame(kStart + 1000 * k, k + 1, "ghost" + std::to_string(k), {0, 0, 0}));
    SpawnRequest spawn;
    spawn.sender = "sender" + std::to_string(k);
    spawn.model = "teapot" + std::to_string(k);
    core.on_command(spawn);
  }
  EXPECT_EQ(core.rejected_total(), 10000);
  EXPECT_LE(core.rejections().size(), 65u);
}

// The same on 1 and 2 worker threads (CoreOptions::threads), the main job's scene shoved by its box.
TEST(SimulatorCore, SameInputsGiveIdenticalWorlds) {
  auto run = [](int threads) {
    CoreOptions options;
    options.threads = threads;
    SimulatorCore core(config::load_scene(kScenes + "bunny_box_table.yaml"), options);
    for (int k = 0; k <= 60; ++k)
      core.on_tracking(frame(kStart + k * 33'333, k + 1, "box", {0.25 - 0.008 * k, 0.002 * (k % 3), 0.0755}));
    core.advance_to(core.sim_time_of(kStart + 60 * 33'333));
    std::vector<Eigen::Matrix4d> poses;
    for (const auto& body : core.world().body_copies()) poses.push_back(body.X_WB.matrix());
    return poses;
  };
  const auto a = run(1), b = run(1), c = run(2);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], b[i]) << "body " << i;  // bit for bit
    EXPECT_EQ(a[i], c[i]) << "body " << i << " on 2 threads";
  }
}

// Application 1: the tracked spoon moves into the virtual teacup's wall; its proxy
// stops at the time of impact, the contact is reported, and it never enters the cup.
TEST(SimulatorCore, SpoonProxyStopsAtTheTeacup) {
  config::SceneConfig scene = config::load_scene(kScenes + "spoon_teacup.yaml");
  SimulatorCore core(scene, {});
  const int spoon = core.world().find("spoon");
  const int cup = core.world().find("teacup");
  ASSERT_GE(spoon, 0);
  ASSERT_GE(cup, 0);
  bool contact = false;
  std::vector<double> proxy_x;
  for (int k = 0; k <= 60; ++k) {
    core.on_tracking(frame(kStart + k * 33'333, k + 1, "spoon", {0.3 - 0.005 * k, 0, 0.035}));  // into the wall at x ~ 0.08
    core.advance_to(core.sim_time_of(kStart + k * 33'333));
    contact |= !core.proxy_contacts().empty();
    proxy_x.push_back(core.world().body_state(spoon).X_WB.translation().x());
    const auto& bodies = core.world().body_copies();
    ASSERT_FALSE(collision::intersects(*bodies[spoon].shape.triangles(), bodies[spoon].X_WB, *bodies[cup].shape.triangles(),
                                       bodies[cup].X_WB))
        << "frame " << k;
  }
  EXPECT_TRUE(contact);
  // Tracking says x = 0.0 now; the proxy stopped at the wall (it may creep along the
  // surface towards the tracked pose, never into the cup).
  EXPECT_GT(proxy_x.back(), 0.03);
}

}  // namespace
}  // namespace arphys::sim
