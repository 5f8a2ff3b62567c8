// The simulator as a real process on real LCM multicast: tracked poses in, world states
// and heartbeats out; malformed and invalid messages are counted and dropped.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "tests/support/launch_watch.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/spawn_process.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7992?ttl=0";


arphys::object_poses_t box_frame(int64_t utime, int64_t seq, double x) {
  arphys::object_poses_t m{};
  m.utime = utime;
  m.seq = seq;
  m.camera_id = "test";
  m.tracker_implementation = "test";
  arphys::object_pose_t o{};
  o.object_id = "box";
  o.status = arphys::object_pose_t::STATUS_TRACKED;
  o.world_valid = true;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(x, 0, 0.0755);
  o.X_WO = arphys::msg::to_message(X);
  o.X_CO = o.X_WO;
  m.objects.push_back(o);
  m.num_objects = 1;
  return m;
}

// The test's side of the bus: every heartbeat and (unless told not to: a 1000-box world
// state every step is a lot to decode) every world state, as they come.
struct SimulatorWatch {
  explicit SimulatorWatch(const std::string& url, bool keep_world_states = true) : bus(url) {
    if (keep_world_states)
      bus.subscribe<arphys::world_state_t>("ARPHYS_WORLD_STATE",
                                           [this](const arphys::world_state_t& m, const lcm::ReceiveBuffer&,
                                                  const std::string&) { states.push_back(m); });
    bus.subscribe<arphys::process_status_t>("ARPHYS_STATUS",
                                            [this](const arphys::process_status_t& m, const lcm::ReceiveBuffer&,
                                                   const std::string&) { statuses.push_back(m); });
  }
  arphys::msg::Bus bus;
  std::vector<arphys::world_state_t> states;
  std::vector<arphys::process_status_t> statuses;
};

// The simulator process on a scene, with extra arguments.
pid_t start_simulator(const std::string& scene, const std::string& url, std::vector<std::string> args) {
  std::vector<std::string> command{std::string(ARPHYS_BINARY_DIR) + "/simulator/app/arphys-simulator",
                                   std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/" + scene, "--lcm-url", url};
  command.insert(command.end(), args.begin(), args.end());
  return arphys::testing::spawn_process(command);
}

TEST(SimulatorProcess, FollowsTrackedPosesAndCountsBadMessages) {
  if (!arphys::testing::multicast_works(kUrl))
    GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  SimulatorWatch watch(kUrl);
  const pid_t sim = start_simulator("bunny_box_table.yaml", kUrl, {"--clock", "messages", "--duration", "20"});
  ASSERT_GT(sim, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // let it load the scene and join the group

  const int64_t t0 = arphys::msg::now_utime();
  // Garbage on the tracking channel, and a frame with a NaN pose: counted, dropped.
  const char garbage[] = "definitely not an object_poses_t";
  watch.bus.publish_raw("ARPHYS_OBJECT_POSES", garbage, sizeof garbage);
  arphys::object_poses_t nan_frame = box_frame(t0 - 1000, 0, 0.25);
  nan_frame.objects[0].X_WO.position_m[0] = std::nan("");
  watch.bus.publish("ARPHYS_OBJECT_POSES", nan_frame);
  // One second of a tracked box moving -x at 0.3 m/s, at 30 Hz (replayed time: capture
  // stamps spaced by 33 ms, sent faster than real time).
  for (int k = 0; k <= 30; ++k) {
    watch.bus.publish("ARPHYS_OBJECT_POSES", box_frame(t0 + k * 33'333, k + 1, 0.25 - 0.01 * k));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    watch.bus.handle_pending();
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline &&
         (watch.states.empty() || watch.states.back().sim_time_s < 0.99 || watch.statuses.size() < 2))
    watch.bus.handle_timeout_ms(100);
  const int status = arphys::testing::stop_process(sim);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "exit status " << status;

  ASSERT_FALSE(watch.states.empty());
  const arphys::world_state_t& last = watch.states.back();
  EXPECT_NEAR(last.sim_time_s, 1.0, 0.02);
  EXPECT_EQ(last.utime, t0 + 30 * 33'333);  // the newest capture used
  EXPECT_EQ(last.seq, 31);
  bool found_box = false;
  int bunnies = 0;
  for (const auto& body : last.bodies) {
    if (body.body_id == "box") {
      found_box = true;
      EXPECT_NEAR(body.X_WB.position_m[0], -0.04, 7e-3);  // one frame behind -0.05, to within a 20 ms step
    }
    bunnies += body.model == "bunny";
  }
  EXPECT_TRUE(found_box);
  EXPECT_GE(bunnies, 1);
  ASSERT_FALSE(watch.statuses.empty());
  EXPECT_EQ(watch.statuses.back().name, "simulator");
  EXPECT_GE(watch.statuses.back().decode_errors, 1);
  EXPECT_GE(watch.statuses.back().rejected, 1);
  EXPECT_GT(watch.statuses.back().published, 25);  // 1 s at 50 steps per second
}

// A live simulator held up (here stopped for 1.5 s, as a starved process is) while the
// camera goes on: with --max-lag-s it gives the backlog up and is back within the bound of
// the newest capture at once, instead of stepping through the 1.5 s it missed.
TEST(SimulatorProcess, AHeldUpSimulatorGivesUpItsBacklogPastMaxLag) {
  // Its own port: ctest runs the tests of this file side by side.
  const std::string url = "udpm://239.255.76.67:7990?ttl=0";
  if (!arphys::testing::multicast_works(url))
    GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  SimulatorWatch watch(url);
  const double max_lag_s = 0.1;
  const pid_t sim = start_simulator("bunny_box_table.yaml", url,
                                    {"--clock", "messages", "--max-lag-s", std::to_string(max_lag_s), "--duration", "20"});
  ASSERT_GT(sim, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // let it load the scene and join the group
  // 3 s of a tracked box moving +x at 0.1 m/s, in real time at 30 Hz; the simulator is
  // stopped from 1 s to 2.5 s.
  const auto start = std::chrono::steady_clock::now();
  const int64_t t0 = arphys::msg::now_utime();
  int64_t resumed_capture = 0;
  bool stopped = false, resumed = false;
  for (int k = 0; k <= 90; ++k) {
    std::this_thread::sleep_until(start + std::chrono::microseconds(k * 33'333));
    const double t_s = k / 30.0;
    if (!stopped && t_s >= 1.0) stopped = kill(sim, SIGSTOP) == 0;
    if (stopped && !resumed && t_s >= 2.5) {
      resumed = kill(sim, SIGCONT) == 0;
      resumed_capture = t0 + k * 33'333;
    }
    watch.bus.publish("ARPHYS_OBJECT_POSES", box_frame(t0 + k * 33'333, k + 1, 0.1 + 0.1 * t_s));
    watch.bus.handle_pending();
  }
  ASSERT_TRUE(stopped && resumed);
  // (Long enough for a heartbeat after the last capture: they come once a second.)
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(1500);
  while (std::chrono::steady_clock::now() < deadline) watch.bus.handle_timeout_ms(50);
  const int status = arphys::testing::stop_process(sim);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "exit status " << status;

  // The simulation ends as far behind the last capture (3 s) as it gave up: 1.4 s, the stop
  // less the bound (stepping the backlog instead, it would end at 3 s, after some 100 world
  // states from the captures taken after the stop; giving it up, some 30).
  ASSERT_FALSE(watch.states.empty());
  ASSERT_FALSE(watch.statuses.empty());
  const double dropped_s = arphys::msg::figure(watch.statuses.back(), "dropped_time_s").value_or(-1);
  const arphys::world_state_t& last = watch.states.back();
  EXPECT_EQ(last.utime, t0 + 90 * 33'333);
  EXPECT_NEAR(dropped_s, 1.5 - max_lag_s, 0.25);
  EXPECT_NEAR(3.0 - last.sim_time_s, dropped_s, 0.03);
  EXPECT_EQ(watch.statuses.back().dropped, std::llround(dropped_s / 0.02));  // in steps of 20 ms
  int after_the_stop = 0;
  for (const auto& state : watch.states) after_the_stop += state.utime >= resumed_capture;
  EXPECT_LE(after_the_stop, 45);
  std::printf("given up %.3f s; %d world states from captures after the stop\n", dropped_s, after_the_stop);
}

// A simulator that is always behind (a 1000-box pile at 1 ms steps, some 20 ms each, on the
// wall clock) keeps giving time up and still publishes its heartbeat once a second: the
// steps of a batch go on to where the batch was to end, not to the newest clock reading.
// What the process refuses at its start, and what it starts afresh from: a bad scene file
// is an exit with code 2 naming the file and the key; a state file that does not decode, or
// that another scene left, is said to be so, and the scene starts as configured.
TEST(SimulatorProcess, BadSceneRefusedAndForeignOrCorruptStateFilesStartAfresh) {
  const std::string url = "udpm://239.255.76.67:7984?ttl=0";  // its own port, as above
  if (!arphys::testing::multicast_works(url))
    GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  const std::string dir = ::testing::TempDir() + "simulator_start/";
  std::filesystem::create_directories(dir);
  const std::string simulator = std::string(ARPHYS_BINARY_DIR) + "/simulator/app/arphys-simulator ";
  std::ofstream(dir + "bad_scene.yaml") << "name: bad\nphysics: {time_step_s: 0.5}\nobjects:\n"
                                           "  - {id: floor, role: real, motion: static, collision: {shape: plane}}\n";
  arphys::testing::CommandRun run = arphys::testing::run_command(simulator + dir + "bad_scene.yaml --lcm-url '" + url + "'");
  EXPECT_EQ(run.exit_code, 2) << run.out;
  EXPECT_NE(run.out.find(dir + "bad_scene.yaml"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("physics.time_step_s: got 0.5, expected a time step of at most 0.1 s"), std::string::npos) << run.out;

  const std::string scene = std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunny_box_table.yaml";
  run = arphys::testing::run_command(simulator + scene + " --catch-up-factor 0.5 --duration 0.5 --lcm-url '" + url + "'");
  EXPECT_NE(run.exit_code, 0) << run.out;  // a body that never catches up
  EXPECT_NE(run.out.find("--catch-up-factor"), std::string::npos) << run.out;
  const auto start_with_state = [&](const std::string& state_file) {
    return arphys::testing::run_command(simulator + scene + " --clock wall --duration 0.5 --lcm-url '" + url +
                                        "' --state-file " + state_file);
  };
  std::ofstream(dir + "corrupt.state") << "not a world state";
  run = start_with_state(dir + "corrupt.state");
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find("does not decode as a world state: starting the scene afresh"), std::string::npos) << run.out;
  arphys::world_state_t foreign{};
  foreign.scene_name = "spoon_teacup";
  foreign.num_bodies = 0;
  foreign.num_contacts = 0;
  std::vector<uint8_t> bytes(foreign.getEncodedSize());
  foreign.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  std::ofstream(dir + "foreign.state", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  run = start_with_state(dir + "foreign.state");
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find("is of scene 'spoon_teacup', not 'bunny_box_table': starting the scene afresh"), std::string::npos)
      << run.out;
  std::filesystem::remove_all(dir);
}

TEST(SimulatorProcess, AnAlwaysBehindSimulatorStillBeatsOnceASecond) {
  const std::string url = "udpm://239.255.76.67:7989?ttl=0";  // its own port, as above
  if (!arphys::testing::multicast_works(url))
    GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  SimulatorWatch watch(url, /*keep_world_states=*/false);
  const pid_t sim = start_simulator("drop1000.yaml", url, {"--clock", "wall", "--max-lag-s", "0.1", "--duration", "30"});
  ASSERT_GT(sim, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(6);
  while (std::chrono::steady_clock::now() < deadline) watch.bus.handle_timeout_ms(100);
  const int status = arphys::testing::stop_process(sim);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "exit status " << status;
  ASSERT_GE(watch.statuses.size(), 4u);  // 6 s, the first second or so loading the scene
  for (std::size_t k = 1; k < watch.statuses.size(); ++k)
    EXPECT_LT(watch.statuses[k].uptime_s - watch.statuses[k - 1].uptime_s, 1.6) << "heartbeat " << k;
  const double dropped_s = arphys::msg::figure(watch.statuses.back(), "dropped_time_s").value_or(0);
  EXPECT_GT(dropped_s, 1.0);  // it simulates a small part of each second
  std::printf("%zu heartbeats, %.2f s given up by uptime %.1f s\n", watch.statuses.size(), dropped_s, watch.statuses.back().uptime_s);
}

}  // namespace
