// Hostile traffic against the running pipeline (application 2 through the launcher):
// arphys-fault sends random and truncated bytes on every channel, bad images, NaN and
// non-unit poses, frames going backwards, camera frames replayed, a spawn flood and image
// bursts. No process
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
#include "lcmtypes/msg/heartbeat.hpp"
#include "tests/support/launch_watch.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7664?ttl=0";

TEST(FaultInjection, PipelineSurvivesHostileTrafficAndCountsIt) {
  if (!arphys::testing::multicast_works(kUrl)) GTEST_SKIP() << "no multicast route (ip route add 224.0.0.0/4 dev lo)";
  arphys::testing::LaunchWatch run(kUrl);
  run.start(9, "", ::testing::TempDir() + "fault_injection_test");
  run.pump_for(2.5);
  std::thread fault([&] {
    std::system((std::string(ARPHYS_BINARY_DIR) + "/tools/fault_inject/arphys-fault --lcm-url " + kUrl +
                 " --duration 4 > " + run.out + "_fault.log 2>&1")
                    .c_str());
  });
  run.pump_for(10.0);
  fault.join();
  EXPECT_TRUE(run.wait()) << "a process died: see " << run.out << ".log";
  const auto& world = run.world;
  auto& last = run.last;
  EXPECT_GT(world.states, 150);  // 50 per second
  EXPECT_EQ(world.non_finite, 0);
  EXPECT_EQ(world.teleports, 0) << world.teleport_body;
  // The launch guard's absolute bound. (Bunnies are thrown at 0.3 m/s and pushed at 0.5 m/s;
  // a pile pushed by the box has launched one at 8 m/s: docs/dynamics.md, a known fault.)
  EXPECT_LT(world.fastest_m_s, 60.0) << world.fastest_body << " at " << world.fastest_at_s << " s";
  std::printf("fastest virtual body on the table: %.2f m/s (%s)\n", world.fastest_m_s, world.fastest_body.c_str());
  ASSERT_EQ(last.count("simulator"), 1u);
  ASSERT_EQ(last.count("tracker"), 1u);
  ASSERT_EQ(last.count("renderer"), 1u);
  EXPECT_GT(last["simulator"].decode_errors, 0);  // random bytes
  EXPECT_GT(last["simulator"].rejected, 0);       // NaN poses, unknown objects, old frames, spawn flood
  EXPECT_GT(last["tracker"].decode_errors, 0);    // random bytes, bad JPEGs, unknown formats
  EXPECT_GT(last["tracker"].rejected, 0);         // wrong-size frames, bad controls
  EXPECT_GT(last["renderer"].decode_errors, 0);
  EXPECT_GT(last["renderer"].rejected, 0);
  // Camera frames sent twice or older than one already seen: refused by name, not drawn or
  // tracked again.
  EXPECT_GT(arphys::msg::figure(last["renderer"], "duplicate camera frame").value_or(0), 0);
  EXPECT_GT(arphys::msg::figure(last["renderer"], "out-of-order camera frame").value_or(0), 0);
  EXPECT_GT(arphys::msg::figure(last["tracker"], "duplicate_or_out_of_order_frames").value_or(0), 0);
}

}  // namespace
