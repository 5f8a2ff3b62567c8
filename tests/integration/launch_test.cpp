// The pipeline through its launcher: synthetic camera, tracker, simulator and renderer
// on real LCM for a few seconds; every frame crosses every stage, the overlay video and
// the latency report are written, and the run ends with exit code 0.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "lcm/lcm-cpp.hpp"
#include "tests/support/run_command.hpp"

namespace {

TEST(Launch, RunsApplicationTwoAndReportsLatency) {
  const std::string url = "udpm://239.255.76.67:7996?ttl=0";
  {
    lcm::LCM probe(url);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  const std::string out = ::testing::TempDir() + "launch_test";
  std::filesystem::remove_all(out);
  const std::string command = std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                              "/tools/arphys-launch " + ARPHYS_SOURCE_DIR +
                              "/configs/scenes/bunny_box_table.yaml --duration 4 --record --lcm-url " + url +
                              " --out " + out;
  const arphys::testing::CommandRun run = arphys::testing::run_command(command);
  ASSERT_EQ(run.exit_code, 0) << run.out;
  ASSERT_TRUE(std::filesystem::exists(out + "/latency.json")) << run.out;
  EXPECT_GT(std::filesystem::file_size(out + "/overlay.avi"), 100000u);
  EXPECT_GT(std::filesystem::file_size(out + "/run.lcmlog"), 100000u);
  nlohmann::json report;
  std::ifstream(out + "/latency.json") >> report;
  const int captured = report["frames"]["captured"];
  EXPECT_GE(captured, 100);  // 4 s at 30 FPS
  EXPECT_GE(report["frames"]["tracked"].get<int>(), captured - 3);
  EXPECT_GE(report["frames"]["rendered"].get<int>(), captured - 3);
  EXPECT_GE(report["stages"]["pose_to_world_state"]["count"].get<int>(), captured - 5);
  EXPECT_GT(report["stages"]["capture_to_overlay"]["p50_ms"].get<double>(), 0.0);
  // The run ended once the pipeline had carried the camera's last frame through (no frame
  // message for half a second), not at the drain's 2.5 s bound; the recording below has
  // every stage's messages, as many as the launcher counted.
  EXPECT_EQ(report["drain"]["ended_by"], "settled") << report["drain"].dump();
  EXPECT_LT(report["drain"]["seconds"].get<double>(), 2.5);

  // The same figures from the recording: the stamps travel inside the messages.
  const std::string from_log = out + "/from_log";
  std::filesystem::create_directories(from_log);
  ASSERT_EQ(std::system((std::string(ARPHYS_BINARY_DIR) + "/tools/launch/arphys-latency " + out + "/run.lcmlog --out " +
                         from_log + " > /dev/null").c_str()),
            0);
  nlohmann::json replayed;
  std::ifstream(from_log + "/latency.json") >> replayed;
  for (const char* stage : {"capture_to_detection", "detection_to_pose", "pose_to_world_state", "capture_to_overlay"}) {
    // Two UDP receivers (the launcher, lcm-logger): equal unless one of them lost a packet.
    EXPECT_NEAR(replayed["stages"][stage]["count"].get<double>(), report["stages"][stage]["count"].get<double>(), 2) << stage;
    EXPECT_NEAR(replayed["stages"][stage]["p50_ms"].get<double>(), report["stages"][stage]["p50_ms"].get<double>(), 1.0)
        << stage;
  }
  std::filesystem::remove_all(out);
}

}  // namespace
