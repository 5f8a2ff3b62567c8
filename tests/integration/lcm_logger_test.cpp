// Real LCM multicast on the host (ttl=0) with Debian's lcm-logger: our types are
// published by one LCM instance, recorded by the real logger process, and read back
// from the log file with the generated decoders. Also runs the README's main tool.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/spawn_process.hpp"

namespace {

// Ports of their own so parallel test runs (these two tests among them) and a live
// pipeline do not mix.
const std::string kUrl = "udpm://239.255.76.67:7991?ttl=0";
const std::string kSceneInfoUrl = "udpm://239.255.76.67:7987?ttl=0";


bool multicast_available() {
  lcm::LCM probe(kUrl);
  return probe.good();
}

TEST(LcmLogger, RecordsOurTypesAndTheyDecodeFromTheLog) {
  if (!multicast_available()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  const std::string log_path = ::testing::TempDir() + "arphys_logger_test.lcmlog";
  std::filesystem::remove(log_path);
  const pid_t logger = arphys::testing::spawn_process({"lcm-logger", "-q", "-f", "--lcm-url=" + kUrl, "-c", "ARPHYS_TEST_.*", log_path});
  ASSERT_GT(logger, 0) << "could not start lcm-logger (apt-get install liblcm-bin)";

  arphys::msg::Bus bus(kUrl);
  // The logger needs a moment to join the group; publish until it has written enough.
  constexpr int kMessages = 40;
  for (int i = 0; i < kMessages; ++i) {
    arphys::world_state_t ws{};
    ws.utime = 1000 + i;
    ws.seq = i;
    ws.scene_name = "logger_test";
    ws.bodies.resize(2);
    ws.bodies[1].body_id = "bunny#" + std::to_string(i);
    ws.num_bodies = 2;
    ws.publish_utime = arphys::msg::now_utime();
    bus.publish("ARPHYS_TEST_WORLD", ws);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  kill(logger, SIGINT);
  int status = 0;
  waitpid(logger, &status, 0);

  lcm::LogFile log(log_path, "r");
  ASSERT_TRUE(log.good()) << log_path;
  int decoded = 0;
  int64_t last_seq = -1;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    ASSERT_EQ(event->channel, "ARPHYS_TEST_WORLD");
    arphys::world_state_t ws;
    ASSERT_GE(ws.decode(event->data, 0, event->datalen), 0);
    EXPECT_EQ(ws.scene_name, "logger_test");
    EXPECT_EQ(ws.bodies[1].body_id, "bunny#" + std::to_string(ws.seq));
    EXPECT_GT(ws.seq, last_seq);  // in order, no duplicates
    last_seq = ws.seq;
    ++decoded;
  }
  // Messages published before the logger joined are lost; the later ones must all be there.
  EXPECT_GE(decoded, kMessages / 2);
  EXPECT_EQ(last_seq, kMessages - 1);
}

TEST(SceneInfo, MainToolLoadsBothScenesAndRoundTripsOverLcm) {
  if (!multicast_available()) GTEST_SKIP() << "no multicast route on this host";
  for (const char* scene : {"bunny_box_table", "spoon_teacup"}) {
    const std::string command = std::string(ARPHYS_BINARY_DIR) + "/tools/scene_info/arphys-scene-info " +
                                ARPHYS_SOURCE_DIR + "/configs/scenes/" + scene + ".yaml --lcm-url '" + kSceneInfoUrl + "'";
    const arphys::testing::CommandRun run = arphys::testing::run_command(command);
    EXPECT_EQ(run.exit_code, 0) << run.out;
    EXPECT_NE(run.out.find(std::string("scene ") + scene), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("received back after"), std::string::npos) << run.out;
  }
}

}  // namespace
