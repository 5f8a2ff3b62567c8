// Which world state the renderer draws over a camera frame, and when it stops waiting for
// the frame's own.
#include <gtest/gtest.h>

#include <string>

#include "renderer/process/world_state_matcher.hpp"

namespace arphys::rendering {
namespace {

// States named by the frame (capture utime) they were computed from.
WorldStateMatcher<std::string> states_of(std::initializer_list<int64_t> utimes) {
  WorldStateMatcher<std::string> states(4);
  for (const int64_t utime : utimes) states.add(utime, "from " + std::to_string(utime));
  return states;
}

TEST(WorldStateMatcher, ExactTakesOnlyTheFramesOwnState) {
  const auto states = states_of({100, 133, 166});
  const auto own = states.match(133, MatchPolicy::kExact);
  EXPECT_EQ(own.kind, MatchKind::kExact);
  ASSERT_NE(own.state, nullptr);
  EXPECT_EQ(*own.state, "from 133");
  EXPECT_EQ(states.match(150, MatchPolicy::kExact).state, nullptr);
}

TEST(WorldStateMatcher, NearestEarlierNeverDrawsALaterFramesState) {
  // Arrival order is not frame order.
  const auto states = states_of({166, 100, 133, 233});
  const auto match = states.match(200, MatchPolicy::kNearestEarlier);
  EXPECT_EQ(match.kind, MatchKind::kNearestEarlier);
  EXPECT_EQ(match.capture_utime, 166);
  EXPECT_EQ(states.match(50, MatchPolicy::kNearestEarlier).kind, MatchKind::kNone);
  EXPECT_EQ(states.match(133, MatchPolicy::kNearestEarlier).kind, MatchKind::kExact);
  // Latest: the newest by arrival, whatever its frame.
  EXPECT_EQ(states.match(50, MatchPolicy::kLatest).capture_utime, 233);
}

TEST(WorldStateMatcher, HasReachedAFrameOnceItsOwnOrALaterStateArrived) {
  auto states = states_of({100});
  EXPECT_TRUE(states.has_reached(100));
  EXPECT_FALSE(states.has_reached(133));  // its own state may still come
  states.add(166, "from 166");            // the simulator skipped 133 (two frames in one step)
  EXPECT_TRUE(states.has_reached(133));
  EXPECT_FALSE(states.has_reached(200));
  EXPECT_FALSE(WorldStateMatcher<std::string>().has_reached(0));
}

TEST(WorldStateMatcher, KeepsTheNewestByArrival) {
  auto states = states_of({100, 133, 166, 200});
  states.add(233, "from 233");  // capacity 4: the state from 100 goes
  EXPECT_EQ(states.match(100, MatchPolicy::kExact).state, nullptr);
  EXPECT_EQ(states.match(133, MatchPolicy::kExact).kind, MatchKind::kExact);
}

TEST(WorldStateMatcher, AReplayedStateIsNotKeptTwice) {
  WorldStateMatcher<std::string> states(4);
  EXPECT_TRUE(states.add(100, "step 1", 5001));
  EXPECT_TRUE(states.add(100, "step 2", 5002));  // a second step from the same frame
  EXPECT_FALSE(states.add(100, "step 1 again", 5001));
  EXPECT_TRUE(states.add(133, "step 3", 5001));  // same stamp, other frame: not a copy
  // The copy did not push a real state out of the bounded history.
  EXPECT_TRUE(states.add(166, "step 4", 5004));
  EXPECT_EQ(*states.match(100, MatchPolicy::kExact).state, "step 2");
}

TEST(WorldStateMatcher, AnUnknownPolicyIsRefusedByName) {
  EXPECT_EQ(match_policy_from("exact"), MatchPolicy::kExact);
  EXPECT_EQ(std::string(to_string(match_policy_from("nearest-earlier"))), "nearest-earlier");
  try {
    match_policy_from("closest");
    FAIL() << "accepted an unknown policy";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'closest'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arphys::rendering
