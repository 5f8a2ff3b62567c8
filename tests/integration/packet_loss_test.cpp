// 20 % packet loss: application 2 runs through the launcher with every process dropping
// a fifth of what it receives (camera frames, poses, world states, commands), at random.
// Nothing dies, each process reports about 20 % of its traffic lost, the pipeline still
// tracks, simulates and draws most frames, and no virtual body jumps: a lost pose makes
// the tracked box move over a longer screw motion, not teleport.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include <nlohmann/json.hpp>

#include "arphys/process_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "tests/support/world_watch.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7662?ttl=0";

double figure(const arphys::process_status_t& status, const std::string& name) {
  for (int i = 0; i < status.num_figures; ++i) {
    if (status.figure_names[i] == name) return status.figure_values[i];
  }
  return -1;
}

TEST(PacketLoss, PipelineRunsThroughTwentyPercentLoss) {
  {
    lcm::LCM probe(kUrl);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  arphys::msg::Bus bus(kUrl);
  std::map<std::string, arphys::process_status_t> last;
  arphys::testing::WorldWatch world;
  bus.subscribe<arphys::process_status_t>("ARPHYS_STATUS", [&](const arphys::process_status_t& m,
                                                               const lcm::ReceiveBuffer&, const std::string&) {
    last[m.name] = m;
  });
  bus.subscribe<arphys::world_state_t>("ARPHYS_WORLD_STATE", [&](const arphys::world_state_t& m,
                                                                 const lcm::ReceiveBuffer&,
                                                                 const std::string&) { world.on_world_state(m); });
  const std::string out = ::testing::TempDir() + "packet_loss_test";
  std::filesystem::remove_all(out);
  int status = -1;
  std::thread launcher([&] {
    status = std::system((std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                          "/tools/arphys-launch " + ARPHYS_SOURCE_DIR +
                          "/configs/scenes/bunny_box_table.yaml --duration 10 --receive-loss 0.2 --lcm-url " + kUrl +
                          " --out " + out + " > " + out + ".log 2>&1")
                             .c_str());
  });
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(14);
  while (std::chrono::steady_clock::now() < end) bus.handle_timeout_ms(10);
  launcher.join();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a process died: see " << out << ".log";
  for (const std::string name : {"tracker", "simulator", "renderer"}) {
    ASSERT_EQ(last.count(name), 1u) << name;
    const double lost = figure(last[name], "injected_losses");
    const double offered = lost + static_cast<double>(last[name].received);
    ASSERT_GT(offered, 100) << name;
    EXPECT_NEAR(lost / offered, 0.2, 0.05) << name;
  }
  EXPECT_EQ(world.non_finite, 0);
  EXPECT_GT(world.states, 500);
  // Bunnies are thrown at 0.3 m/s and pushed at 0.5 m/s: 5 m/s would be a launch.
  EXPECT_LT(world.fastest_m_s, 5.0) << world.fastest_body << " at " << world.fastest_at_s << " s";
  nlohmann::json report;
  std::ifstream(out + "/latency.json") >> report;
  const int captured = report["frames"]["captured"].get<int>();
  const int rendered = report["frames"]["rendered"].get<int>();
  // The renderer loses a fifth of the frames itself; the rest are drawn (a lost world
  // state only makes it use the one before).
  EXPECT_GT(rendered, captured * 6 / 10) << rendered << " of " << captured;
  std::printf("packet loss 20 %%: %d of %d frames drawn, fastest virtual body %.2f m/s, capture->overlay p50 %.1f "
              "p99 %.1f ms\n",
              rendered, captured, world.fastest_m_s,
              report["stages"]["capture_to_overlay"]["p50_ms"].get<double>(),
              report["stages"]["capture_to_overlay"]["p99_ms"].get<double>());
}

}  // namespace
