// Process faults: during a run of application 2 the tracker, the simulator and the
// renderer are killed (SIGKILL) in turn. With --restart the launcher brings each back on
// the same channels; the others keep running; the run ends with exit code 0, the restarts
// are reported, and frames keep being tracked, simulated and drawn after each restart.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "arphys/render_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7663?ttl=0";

void kill_process_named(const std::string& executable) {
  std::system(("pkill -9 -f '" + executable + ".*7663' > /dev/null 2>&1").c_str());
}

TEST(ProcessRestart, KilledProcessesComeBackAndTheRunGoesOn) {
  {
    lcm::LCM probe(kUrl);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  arphys::msg::Bus bus(kUrl);
  std::vector<double> world_times, render_times;  // seconds since the test started
  const auto t0 = std::chrono::steady_clock::now();
  auto now_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  bus.subscribe<arphys::world_state_t>("ARPHYS_WORLD_STATE", [&](const arphys::world_state_t&, const lcm::ReceiveBuffer&,
                                                                 const std::string&) { world_times.push_back(now_s()); });
  bus.subscribe<arphys::render_status_t>("ARPHYS_RENDER_STATUS", [&](const arphys::render_status_t&,
                                                                     const lcm::ReceiveBuffer&,
                                                                     const std::string&) { render_times.push_back(now_s()); });
  const std::string out = ::testing::TempDir() + "process_restart_test";
  std::filesystem::remove_all(out);
  int status = -1;
  std::thread launcher([&] {
    status = std::system((std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                          "/tools/arphys-launch " + ARPHYS_SOURCE_DIR +
                          "/configs/scenes/bunny_box_table.yaml --duration 12 --restart --lcm-url " + kUrl + " --out " +
                          out + " > " + out + ".log 2>&1")
                             .c_str());
  });
  auto pump_until = [&](double t) {
    while (now_s() < t) bus.handle_timeout_ms(10);
  };
  pump_until(3.5);
  kill_process_named("tracker/app/tracker");
  pump_until(6.0);
  kill_process_named("simulator/app/arphys-simulator");
  pump_until(8.5);
  kill_process_named("renderer/app/renderer");
  pump_until(16.5);
  launcher.join();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "see " << out << ".log";
  nlohmann::json report;
  std::ifstream(out + "/latency.json") >> report;
  EXPECT_EQ(report["restarts"]["tracker"], 1);
  EXPECT_EQ(report["restarts"]["simulator"], 1);
  EXPECT_EQ(report["restarts"]["renderer"], 1);
  // After the last kill the pipeline is whole again: world states and overlays keep coming.
  const auto after = [](const std::vector<double>& times, double t) {
    return std::count_if(times.begin(), times.end(), [t](double x) { return x > t; });
  };
  EXPECT_GT(after(world_times, 10.5), 100);  // 100 steps per second
  EXPECT_GT(after(render_times, 10.5), 30);  // 30 frames per second
  EXPECT_GT(report["frames"]["rendered"].get<int>(), report["frames"]["captured"].get<int>() / 2);
  // The gaps each restart left (printed for docs/ROBUSTNESS.md).
  const auto longest_gap = [](const std::vector<double>& times) {
    double gap = 0;
    for (std::size_t i = 1; i < times.size(); ++i) gap = std::max(gap, times[i] - times[i - 1]);
    return gap;
  };
  std::printf("longest gap: world states %.2f s, overlays %.2f s\n", longest_gap(world_times), longest_gap(render_times));
}

}  // namespace
