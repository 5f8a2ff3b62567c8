// Record and replay: a short synthetic run (camera + tracker) is recorded with
// lcm-logger through the launcher, then its tracked poses are played twice with
// lcm-logplayer into a fresh simulator (clock from the messages): the two runs give
// identical world states, bit for bit; and so does arphys-replay's.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "tests/support/spawn_process.hpp"

namespace {

const std::string kRecordUrl = "udpm://239.255.76.67:7997?ttl=0";
const std::string kReplayUrl = "udpm://239.255.76.67:7998?ttl=0";

int run(const std::string& command) {
  const int status = std::system((command + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// World states keyed by simulation time: the bodies' poses as published.
using Trace = std::map<double, std::vector<std::array<double, 7>>>;

// player: the command that plays the log's tracked poses onto kReplayUrl.
Trace replay_once(const std::string& player_command) {
  arphys::msg::Bus bus(kReplayUrl);
  Trace trace;
  bus.subscribe<arphys::world_state_t>("ARPHYS_WORLD_STATE", [&](const arphys::world_state_t& m,
                                                                 const lcm::ReceiveBuffer&, const std::string&) {
    auto& bodies = trace[m.sim_time_s];
    bodies.clear();
    for (const auto& b : m.bodies) {
      bodies.push_back({b.X_WB.position_m[0], b.X_WB.position_m[1], b.X_WB.position_m[2], b.X_WB.orientation_wxyz[0],
                        b.X_WB.orientation_wxyz[1], b.X_WB.orientation_wxyz[2], b.X_WB.orientation_wxyz[3]});
    }
  });
  const pid_t simulator = arphys::testing::spawn_process(
      {std::string(ARPHYS_BINARY_DIR) + "/simulator/app/arphys-simulator",
       std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunny_box_table.yaml", "--lcm-url", kReplayUrl, "--clock",
       "messages", "--duration", "60"});
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  std::atomic<bool> played{false};
  std::thread player([&] {
    run(player_command);
    played = true;
  });
  // Until the player has played the log (in real time: about 3 s).
  // (A stuck player would block the join below anyway: the test's timeout ends it.)
  while (!played) bus.handle_timeout_ms(20);
  player.join();
  for (int i = 0; i < 50; ++i) bus.handle_timeout_ms(20);
  arphys::testing::stop_process(simulator);
  return trace;
}

TEST(Replay, TwoReplaysOfARecordingGiveIdenticalWorldStates) {
  {
    lcm::LCM probe(kRecordUrl);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  const std::string out = ::testing::TempDir() + "replay_test";
  std::filesystem::remove_all(out);
  ASSERT_EQ(run(std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR + "/tools/arphys-launch " +
                ARPHYS_SOURCE_DIR + "/configs/scenes/bunny_box_table.yaml --only camera,tracker --duration 3 --record " +
                "--lcm-url " + kRecordUrl + " --out " + out),
            0);
  const std::string log = out + "/run.lcmlog";
  ASSERT_TRUE(std::filesystem::exists(log));

  const Trace first = replay_once("lcm-logplayer -e ARPHYS_OBJECT_POSES --lcm-url=" + kReplayUrl + " " + log);
  const Trace second = replay_once("lcm-logplayer -e ARPHYS_OBJECT_POSES --lcm-url=" + kReplayUrl + " " + log);
  const Trace ours = replay_once(std::string(ARPHYS_BINARY_DIR) + "/tools/replay/arphys-replay --channels " +
                                 "ARPHYS_OBJECT_POSES --lcm-url " + kReplayUrl + " " + log + " < /dev/null");
  ASSERT_GT(first.size(), 100u);  // 3 s of tracking at 50 steps per second
  EXPECT_EQ(first.size(), second.size());
  // Of the first replay's world states, how many the other has at the same time, and how
  // many of those differ.
  const auto compare = [&](const Trace& other) {
    std::pair<int, int> compared_different{0, 0};
    for (const auto& [t, bodies] : first) {
      const auto it = other.find(t);
      if (it == other.end()) continue;
      ++compared_different.first;
      if (bodies != it->second) ++compared_different.second;
    }
    return compared_different;
  };
  const auto [compared, different] = compare(second);
  EXPECT_GE(compared, static_cast<int>(first.size()) - 2);
  EXPECT_EQ(different, 0);
  // arphys-replay plays the same events in the same order: the same world states.
  EXPECT_EQ(ours.size(), first.size());
  const auto [ours_compared, ours_different] = compare(ours);
  EXPECT_GE(ours_compared, static_cast<int>(first.size()) - 2);
  EXPECT_EQ(ours_different, 0);
  // The launcher replays the same log into a simulator of its own (arphys-launch --replay):
  // every recorded tracking frame reaches a world state, and the run ends with the log.
  const std::string replayed = out + "/replayed";
  ASSERT_EQ(
      run(std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR + "/tools/arphys-launch " +
          ARPHYS_SOURCE_DIR + "/configs/scenes/bunny_box_table.yaml --replay " + log +
          " --replay-what poses --only camera,simulator --duration 8 --lcm-url " + kReplayUrl + " --out " + replayed),
      0);
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(replayed + "/latency.json"));
  // 3 s of a 30 FPS camera: about 90.
  EXPECT_GE(report["stages"]["pose_to_world_state"]["count"].get<int>(), 80) << report["stages"].dump();
  // The tracked box moved: the replay drove the simulator, not the scene's initial pose.
  const auto& box_start = first.begin()->second;
  const auto& box_end = first.rbegin()->second;
  ASSERT_GE(box_start.size(), 2u);
  EXPECT_GT(std::abs(box_end[1][0] - box_start[1][0]), 0.01);
  std::filesystem::remove_all(out);
}

}  // namespace
