// When the live renderer draws a camera frame: at once, after waiting for its own world
// state, or never (superseded, replayed, older).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "renderer/process/frame_schedule.hpp"

namespace arphys::rendering {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

struct Frame {
  std::string camera_id = "cam";
  int64_t seq = 0;
  int64_t utime = 0;
};

Frame frame(int64_t seq) { return {"cam", seq, 1000 * seq}; }

std::vector<int64_t> seqs(const std::vector<Frame>& frames) {
  std::vector<int64_t> out;
  for (const Frame& f : frames) out.push_back(f.seq);
  return out;
}

// The world states that have arrived, by the capture utime they were computed from.
struct Arrived {
  std::set<int64_t> utimes;
  std::function<bool(int64_t)> reached() {
    return [this](int64_t utime) { return !utimes.empty() && *utimes.rbegin() >= utime; };
  }
};

TEST(FrameSchedule, WithoutAWaitTheNewestFrameIsDueAndOlderOnesDropped) {
  Arrived arrived;
  FrameSchedule<Frame> schedule({0, MatchPolicy::kNearestEarlier}, arrived.reached());
  const auto t0 = Clock::now();
  schedule.offer(frame(1), t0);
  schedule.offer(frame(2), t0);
  schedule.offer(frame(3), t0);
  EXPECT_EQ(seqs(schedule.take_due(t0)), (std::vector<int64_t>{3}));
  EXPECT_EQ(schedule.dropped(), 2);
  EXPECT_TRUE(schedule.take_due(t0).empty());
  EXPECT_EQ(schedule.past_the_wait(), 0);  // nothing could have waited
}

TEST(FrameSchedule, AFrameWaitsForItsOwnStateUntilItArrives) {
  Arrived arrived;
  FrameSchedule<Frame> schedule({30, MatchPolicy::kNearestEarlier}, arrived.reached());
  const auto t0 = Clock::now();
  schedule.offer(frame(1), t0);
  EXPECT_NEAR(schedule.wait_left_ms(t0 + milliseconds(10)), 20.0, 1e-9);
  EXPECT_TRUE(schedule.take_due(t0 + milliseconds(10)).empty());
  arrived.utimes.insert(1000);
  EXPECT_EQ(schedule.wait_left_ms(t0 + milliseconds(11)), 0.0);
  EXPECT_EQ(seqs(schedule.take_due(t0 + milliseconds(11))), (std::vector<int64_t>{1}));
  EXPECT_EQ(schedule.past_the_wait(), 0);
}

TEST(FrameSchedule, AtTheWaitsEndTheFrameIsDrawnWithoutItsOwnAndCounted) {
  Arrived arrived;
  FrameSchedule<Frame> schedule({30, MatchPolicy::kExact}, arrived.reached());
  const auto t0 = Clock::now();
  schedule.offer(frame(1), t0);
  EXPECT_TRUE(schedule.take_due(t0 + milliseconds(29)).empty());
  EXPECT_EQ(seqs(schedule.take_due(t0 + milliseconds(31))), (std::vector<int64_t>{1}));
  EXPECT_EQ(schedule.past_the_wait(), 1);
}

TEST(FrameSchedule, AWaitingFrameIsDrawnNotDroppedWhenANewerOneComes) {
  Arrived arrived;
  FrameSchedule<Frame> schedule({30, MatchPolicy::kNearestEarlier}, arrived.reached());
  const auto t0 = Clock::now();
  schedule.offer(frame(1), t0);
  schedule.offer(frame(2), t0 + milliseconds(5));   // 1 was waiting: it is drawn at once
  schedule.offer(frame(3), t0 + milliseconds(6));   // 2 was waiting too, but one is already due
  EXPECT_EQ(seqs(schedule.take_due(t0 + milliseconds(7))), (std::vector<int64_t>{1}));
  EXPECT_EQ(schedule.dropped(), 1);
  EXPECT_EQ(schedule.past_the_wait(), 1);
  arrived.utimes.insert(3000);
  EXPECT_EQ(seqs(schedule.take_due(t0 + milliseconds(8))), (std::vector<int64_t>{3}));
  EXPECT_EQ(schedule.past_the_wait(), 1);
}

TEST(FrameSchedule, TheLatestPolicyNeverWaits) {
  Arrived arrived;
  FrameSchedule<Frame> schedule({30, MatchPolicy::kLatest}, arrived.reached());
  const auto t0 = Clock::now();
  schedule.offer(frame(1), t0);
  EXPECT_EQ(schedule.wait_left_ms(t0), 0.0);
  EXPECT_EQ(seqs(schedule.take_due(t0)), (std::vector<int64_t>{1}));
  EXPECT_EQ(schedule.past_the_wait(), 0);
}

TEST(FrameSchedule, AReplayedOrOlderFrameIsRefusedAndNeverDrawn) {
  Arrived arrived;
  FrameSchedule<Frame> schedule({0, MatchPolicy::kNearestEarlier}, arrived.reached());
  const auto t0 = Clock::now();
  EXPECT_EQ(schedule.offer(frame(5), t0), msg::FrameOrder::Verdict::kNew);
  EXPECT_EQ(seqs(schedule.take_due(t0)), (std::vector<int64_t>{5}));
  EXPECT_EQ(schedule.offer(frame(5), t0), msg::FrameOrder::Verdict::kDuplicate);
  EXPECT_EQ(schedule.offer(frame(4), t0), msg::FrameOrder::Verdict::kOutOfOrder);
  EXPECT_TRUE(schedule.take_due(t0).empty());
  // Another camera's frames are ordered on their own.
  EXPECT_EQ(schedule.offer({"other", 1, 1000}, t0), msg::FrameOrder::Verdict::kNew);
  EXPECT_EQ(schedule.dropped(), 0);
}

TEST(FrameSchedule, AWaitOutsideItsRangeIsRefusedNamingIt) {
  Arrived arrived;
  try {
    FrameSchedule<Frame> schedule({-1, MatchPolicy::kExact}, arrived.reached());
    FAIL() << "accepted a negative wait";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("wait_ms -1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arphys::rendering
