// Five minutes of faults (label slow): application 2 runs through the launcher with 20 %
// receive loss in every process while arphys-fault sends hostile traffic the whole time.
// No process dies, every process's resident memory stays flat after its warm-up (a leak
// of a few hundred bytes per message would show as megabytes), and no virtual body is
// launched or turns non-finite. ARPHYS_SOAK_S sets the length (default 300 s).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/support/launch_watch.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7661?ttl=0";

TEST(Soak, FiveMinutesOfFaultsLeaveMemoryFlat) {
  if (!arphys::testing::multicast_works(kUrl)) GTEST_SKIP() << "no multicast route (ip route add 224.0.0.0/4 dev lo)";
  const double duration_s = std::getenv("ARPHYS_SOAK_S") ? std::atof(std::getenv("ARPHYS_SOAK_S")) : 300.0;
  arphys::testing::LaunchWatch run(kUrl);
  run.start(duration_s, "--receive-loss 0.2", ::testing::TempDir() + "soak_test");
  std::thread fault([&] {
    std::this_thread::sleep_for(std::chrono::seconds(3));
    std::system((std::string(ARPHYS_BINARY_DIR) + "/tools/fault_inject/arphys-fault --lcm-url " + kUrl +
                 " --duration " + std::to_string(duration_s - 5) + " > " + run.out + "_fault.log 2>&1")
                    .c_str());
  });
  run.pump_for(duration_s + 4);
  fault.join();
  ASSERT_TRUE(run.wait()) << "a process died: see " << run.out << ".log";
  const auto& world = run.world;
  EXPECT_EQ(world.non_finite, 0);
  EXPECT_EQ(world.teleports, 0) << world.teleport_body;
  // The launch guard's absolute bound. (Bunnies are thrown at 0.3 m/s and pushed at 0.5 m/s;
  // a pile pushed by the box has launched one at 8 m/s: docs/dynamics.md, a known fault.)
  EXPECT_LT(world.fastest_m_s, 60.0) << world.fastest_body << " at " << world.fastest_at_s << " s";
  nlohmann::json report;
  std::ifstream(run.out + "/latency.json") >> report;
  for (const std::string name : {"tracker", "simulator", "renderer"}) {
    const auto& m = report["memory"][name];
    ASSERT_TRUE(m.contains("growth_mb")) << name;
    std::printf("soak %s: RSS %.1f MB after warm-up, %+.2f MB over %.0f s (max %.1f MB)\n", name.c_str(),
                m["rss_mb_after_warm_up"].get<double>(), m["growth_mb"].get<double>(), m["over_s"].get<double>(),
                m["rss_mb_max"].get<double>());
    EXPECT_LT(m["growth_mb"].get<double>(), 8.0) << name;
  }
  std::printf("soak: %ld world states, fastest virtual body %.2f m/s, frames %s\n", world.states, world.fastest_m_s,
              report["frames"].dump().c_str());
}

}  // namespace
