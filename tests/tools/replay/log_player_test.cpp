// The replay's player on a log written here: what it publishes when, at a rate, from a
// start, on some channels, paused, stepped and sought.
#include "tools/replay/log_player.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/tools/replay/test_log.hpp"

namespace arphys::replay {
namespace {

// A log of FRAME events every 100 ms from t = 0 and POSE events 50 ms after each, ten each,
// the event's data its index in the log.
std::string write_log() {
  // One file per test: ctest runs the tests of this file as parallel processes.
  const std::string path = ::testing::TempDir() + "log_player_test_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".lcmlog";
  testing::write_test_log(path, 20, [](int k) { return k % 2 == 0 ? "FRAME" : "POSE"; });
  return path;
}

struct Played {
  std::vector<int> indices;
  LogPlayer::Publish sink() {
    return [this](const LogEvent& e) { indices.push_back(e.data.at(0)); };
  }
};

TEST(LogPlayer, PlaysEachEventWhenItsTimeComesAtTheRate) {
  LogPlayer player(write_log(), {2.0, 0, ""});
  EXPECT_EQ(player.events(), 20);
  EXPECT_NEAR(player.duration_s(), 0.95, 1e-9);
  Played p;
  EXPECT_TRUE(std::isinf(player.play(10.0, p.sink())));  // paused until resumed
  EXPECT_TRUE(p.indices.empty());
  player.resume(10.0);
  // At twice real time, log second 0.5 (events 0..10) comes 0.25 s after the start.
  const double wait = player.play(10.25, p.sink());
  EXPECT_EQ(p.indices, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  EXPECT_NEAR(wait, 0.025, 1e-9);  // event 11 at 0.55 s of the log
  player.play(11.0, p.sink());
  EXPECT_EQ(p.indices.size(), 20u);
  EXPECT_TRUE(player.finished());
}

TEST(LogPlayer, StartsLaterAndPlaysTheChosenChannels) {
  LogPlayer player(write_log(), {1.0, 0.62, "POSE"});
  Played p;
  player.resume(0);
  player.play(100, p.sink());
  EXPECT_EQ(p.indices, (std::vector<int>{13, 15, 17, 19}));  // POSE at 0.65 s and after
}

TEST(LogPlayer, PauseHoldsStepPlaysToTheNextFrameSeekLandsOnTheTime) {
  LogPlayer player(write_log(), {1.0, 0, ""});
  Played p;
  player.resume(0);
  player.play(0.12, p.sink());  // events 0, 1, 2 (0, 50, 100 ms)
  player.pause(0.12);
  player.play(5.0, p.sink());  // held
  EXPECT_EQ(p.indices, (std::vector<int>{0, 1, 2}));
  EXPECT_NEAR(player.position_s(), 0.15, 1e-9);
  // Resumed at 5.0: log time goes on from 0.12, so event 3 (0.15 s) comes 0.03 s later.
  player.resume(5.0);
  EXPECT_NEAR(player.play(5.0, p.sink()), 0.03, 1e-9);
  player.play(5.03, p.sink());
  EXPECT_EQ(p.indices.back(), 3);
  // A step plays everything up to and including the next FRAME (event 4), then holds.
  player.step("FRAME", p.sink());
  EXPECT_EQ(p.indices.back(), 4);
  EXPECT_TRUE(player.paused());
  player.play(9.0, p.sink());
  EXPECT_EQ(p.indices.back(), 4);
  // Seek to 0.7 s: the next event is 14 (0.70 s); back to 0: event 0 again.
  player.seek(0.7, 9.0);
  EXPECT_NEAR(player.position_s(), 0.7, 1e-9);
  player.step("FRAME", p.sink());
  EXPECT_EQ(p.indices.back(), 14);
  player.seek(-3, 9.0);
  player.step("FRAME", p.sink());
  EXPECT_EQ(p.indices.back(), 0);
}

TEST(LogPlayer, RefusesAMissingLogABadRateAndABadChannelPattern) {
  try {
    LogPlayer player("/nonexistent/run.lcmlog", {});
    FAIL() << "a missing log was opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/run.lcmlog"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LogPlayer(write_log(), {0.0, 0, ""}), std::invalid_argument);
  EXPECT_THROW(LogPlayer(write_log(), {1.0, -1, ""}), std::invalid_argument);
  EXPECT_THROW(LogPlayer(write_log(), {1.0, 0, "(unclosed"}), std::invalid_argument);
  EXPECT_THROW(LogPlayer(write_log(), {1.0, 0, "NOTHING"}), std::runtime_error);
  LogPlayer player(write_log(), {});
  EXPECT_THROW(player.set_rate(-2, 0), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::replay
