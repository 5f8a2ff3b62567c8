#include "tools/launch/supervisor.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace arphys::launch {
namespace {

// Polls until `done` or 5 s.
template <typename F>
void poll_until(F done) {
  const auto start = std::chrono::steady_clock::now();
  while (!done() && std::chrono::steady_clock::now() - start < std::chrono::seconds(5))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

TEST(Supervisor, ExpectedEndIsNotADeathAndADeathIsNamed) {
  const std::string dir = ::testing::TempDir() + "/supervisor_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  Supervisor s(dir);
  ASSERT_TRUE(s.start("camera", {"sh", "-c", "echo frames; exit 0"}));
  ASSERT_TRUE(s.start("simulator", {"sh", "-c", "exit 3"}));
  ASSERT_TRUE(s.start("renderer", {"sleep", "30"}));
  const auto expected = [](const Child& c) { return c.name == "camera" && WIFEXITED(c.status) && WEXITSTATUS(c.status) == 0; };
  std::string died;  // (a death is reported once, by the poll that reaps it)
  poll_until([&] {
    if (const std::string name = s.poll(false, expected); died.empty()) died = name;
    return !died.empty() && s.find("camera")->exited;
  });
  EXPECT_EQ(died, "simulator");
  EXPECT_TRUE(s.find("camera")->exited);
  EXPECT_FALSE(s.find("renderer")->exited);
  s.stop_all();
  EXPECT_TRUE(WIFSIGNALED(s.find("renderer")->status));
  std::stringstream log;
  log << std::ifstream(s.log_of("camera")).rdbuf();
  EXPECT_EQ(log.str(), "frames\n");
  std::filesystem::remove_all(dir);
}

TEST(Supervisor, RestartsADeadProcessIntoNewLogs) {
  const std::string dir = ::testing::TempDir() + "/supervisor_restart_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  Supervisor s(dir);
  ASSERT_TRUE(s.start("tracker", {"sh", "-c", "echo run; exit 1"}));
  const auto never = [](const Child&) { return false; };
  poll_until([&] {
    EXPECT_EQ(s.poll(true, never), "");  // restarted, never reported
    return s.restarts().count("tracker") && s.restarts().at("tracker") >= 2;
  });
  EXPECT_GE(s.restarts().at("tracker"), 2);
  s.stop_all();
  EXPECT_TRUE(std::filesystem::exists(dir + "/tracker.log"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/tracker.1.log"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/tracker.2.log"));
  std::filesystem::remove_all(dir);
}

TEST(Supervisor, AProgramThatCannotStartIsRefused) {
  Supervisor s("");
  EXPECT_FALSE(s.start("ghost", {"/nonexistent/arphys-ghost"}));
}

}  // namespace
}  // namespace arphys::launch
