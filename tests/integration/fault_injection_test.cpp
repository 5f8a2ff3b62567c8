// Hostile traffic against the running pipeline (application 2 through the launcher):
// arphys-fault sends random and truncated bytes on every channel, bad images, NaN and
// non-unit poses, frames going backwards, a spawn flood and image bursts. No process
// dies (the launcher exits 0), every process counts what it refused, and no world state
// ever holds a non-finite pose or a virtual body that jumped.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <thread>

#include "arphys/process_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "tests/support/world_watch.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7664?ttl=0";

TEST(FaultInjection, PipelineSurvivesHostileTrafficAndCountsIt) {
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
  const std::string out = ::testing::TempDir() + "fault_injection_test";
  std::filesystem::remove_all(out);
  int launch_status = -1;
  std::thread launcher([&] {
    launch_status = std::system((std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                                 "/tools/arphys-launch " + ARPHYS_SOURCE_DIR +
                                 "/configs/scenes/bunny_box_table.yaml --duration 9 --lcm-url " + kUrl + " --out " + out +
                                 " > " + out + ".log 2>&1")
                                    .c_str());
  });
  auto pump = [&](double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) bus.handle_timeout_ms(10);
  };
  pump(2.5);
  std::thread fault([&] {
    std::system((std::string(ARPHYS_BINARY_DIR) + "/tools/fault_inject/arphys-fault --lcm-url " + kUrl +
                 " --duration 4 > " + out + "_fault.log 2>&1")
                    .c_str());
  });
  pump(10.0);
  fault.join();
  launcher.join();
  EXPECT_TRUE(WIFEXITED(launch_status) && WEXITSTATUS(launch_status) == 0) << "a process died: see " << out << ".log";
  EXPECT_GT(world.states, 300);
  EXPECT_EQ(world.non_finite, 0);
  // Bunnies are thrown at 0.3 m/s and pushed at 0.5 m/s: 5 m/s would be a launch.
  EXPECT_LT(world.fastest_m_s, 5.0) << world.fastest_body << " at " << world.fastest_at_s << " s";
  ASSERT_EQ(last.count("simulator"), 1u);
  ASSERT_EQ(last.count("tracker"), 1u);
  ASSERT_EQ(last.count("renderer"), 1u);
  EXPECT_GT(last["simulator"].decode_errors, 0);  // random bytes
  EXPECT_GT(last["simulator"].rejected, 0);       // NaN poses, unknown objects, old frames, spawn flood
  EXPECT_GT(last["tracker"].decode_errors, 0);    // random bytes, bad JPEGs, unknown formats
  EXPECT_GT(last["tracker"].rejected, 0);         // wrong-size frames, bad controls
  EXPECT_GT(last["renderer"].decode_errors, 0);
  EXPECT_GT(last["renderer"].rejected, 0);
}

}  // namespace
