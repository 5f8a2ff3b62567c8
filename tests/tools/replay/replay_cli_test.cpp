// arphys-replay as a process, driven by replay_control_t messages: it starts paused and
// publishes nothing, a step publishes one frame, a seek then a step the frame at that time,
// a repeated command is dropped and counted, a resume at four times real time plays the rest
// and the process ends with the log; its status carries the log's duration and position.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "arphys/process_status_t.hpp"
#include "arphys/replay_control_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "tests/support/spawn_process.hpp"
#include "tests/tools/replay/test_log.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7986?ttl=0";  // a port of its own

// 40 events on FRAME, 50 ms apart, each carrying its index.
std::string write_log() {
  const std::string path = ::testing::TempDir() + "replay_cli_test_" + std::to_string(getpid()) + ".lcmlog";
  arphys::replay::testing::write_test_log(path, 40, [](int) { return "FRAME"; });
  return path;
}

class Frames {
 public:
  explicit Frames(lcm::LCM& lcm) { lcm.subscribe("FRAME", &Frames::on_frame, this); }
  void on_frame(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    indices.push_back(static_cast<const uint8_t*>(rbuf->data)[0]);
  }
  std::vector<int> indices;
};

TEST(ReplayCli, ControlMessagesPauseStepSeekAndResume) {
  lcm::LCM lcm(kUrl);
  if (!lcm.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  Frames frames(lcm);
  std::optional<arphys::process_status_t> status;
  arphys::msg::Bus bus(kUrl);
  bus.subscribe<arphys::process_status_t>(
      "REPLAY_STATUS",
      [&](const arphys::process_status_t& s, const lcm::ReceiveBuffer&, const std::string&) { status = s; });
  const pid_t replay = arphys::testing::spawn_process({std::string(ARPHYS_BINARY_DIR) + "/tools/replay/arphys-replay",
                                                       write_log(), "--lcm-url", kUrl, "--paused", "--frame-channel",
                                                       "FRAME", "--status-channel", "REPLAY_STATUS"});
  ASSERT_GT(replay, 0);
  const auto pump = [&](int ms) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < until) {
      lcm.handleTimeout(5);
      bus.handle_timeout_ms(5);
    }
  };
  // Until `done` holds, at most 3 s (a loaded machine is slow, not wrong).
  const auto pump_until = [&](const std::function<bool()>& done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (!done() && std::chrono::steady_clock::now() < until) {
      lcm.handleTimeout(5);
      bus.handle_timeout_ms(5);
    }
  };
  int64_t seq = 0;
  const auto send = [&](const std::string& command, double value, int64_t repeat_seq = -1) {
    arphys::replay_control_t m{};
    m.utime = 1'000'000 + 1000 * (repeat_seq >= 0 ? repeat_seq : ++seq);
    m.seq = repeat_seq >= 0 ? repeat_seq : seq;
    m.sender = "test";
    m.command = command;
    m.value = value;
    bus.publish("ARPHYS_REPLAY_CONTROL", m);
  };
  pump_until([&] { return status.has_value(); });  // started, paused: nothing played, its status out
  pump(300);
  EXPECT_TRUE(frames.indices.empty());
  ASSERT_TRUE(status.has_value()) << "no status from arphys-replay";
  EXPECT_EQ(status->state, "paused");
  EXPECT_NEAR(arphys::msg::figure(*status, "duration_s").value_or(-1), 1.95, 1e-9);
  send("step", 0);
  pump_until([&] { return frames.indices.size() >= 1; });
  EXPECT_EQ(frames.indices, (std::vector<int>{0}));
  send("seek", 1.0);
  send("step", 0);
  pump_until([&] { return frames.indices.size() >= 2; });
  EXPECT_EQ(frames.indices, (std::vector<int>{0, 20}));
  send("step", 0, seq);  // the same command again: dropped
  pump(300);
  EXPECT_EQ(frames.indices.size(), 2u);
  const auto resumed = std::chrono::steady_clock::now();
  send("rate", 4);
  send("resume", 0);
  pump_until([&] { return frames.indices.size() >= 21; });
  // 0.95 s of log at four times real time: about a quarter of a second, not one.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - resumed).count(), 0.9);
  ASSERT_EQ(frames.indices.size(), 21u);
  EXPECT_EQ(frames.indices.back(), 39);
  int wait_status = 0;
  for (int k = 0; k < 100 && waitpid(replay, &wait_status, WNOHANG) == 0; ++k) pump(20);
  EXPECT_TRUE(WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0) << "it ends with the log";
  pump(200);  // its last status
  EXPECT_EQ(status->state, "finished");
  EXPECT_NEAR(arphys::msg::figure(*status, "position_s").value_or(-1), 1.95, 1e-9);
  EXPECT_GE(status->rejected, 1) << "the repeated command is counted";
}

}  // namespace
