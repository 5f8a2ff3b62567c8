// Which frames are new: a replayed message and anything not newer than the newest from
// its source are refused, per source, and ids from messages cannot grow the table.
#include <gtest/gtest.h>

#include <string>

#include "lcmtypes/msg/frame_order.hpp"

namespace arphys::msg {
namespace {

using Verdict = FrameOrder::Verdict;

TEST(FrameOrder, AReplayedOrOlderFrameIsRefusedAndANewerOneTaken) {
  FrameOrder order;
  EXPECT_EQ(order.check("cam", 1, 1000), Verdict::kNew);
  EXPECT_EQ(order.check("cam", 1, 1000), Verdict::kDuplicate);
  EXPECT_EQ(order.check("cam", 0, 900), Verdict::kOutOfOrder);
  EXPECT_EQ(order.check("cam", 2, 1000), Verdict::kOutOfOrder);  // a second frame of the same instant
  EXPECT_EQ(order.check("cam", 2, 1033), Verdict::kNew);
  // A restarted camera counts from 0 again: its capture times still go on.
  EXPECT_EQ(order.check("cam", 0, 2000), Verdict::kNew);
  EXPECT_EQ(order.check("cam", 0, 2000), Verdict::kDuplicate);
  EXPECT_STREQ(to_string(Verdict::kDuplicate), "duplicate");
  EXPECT_STREQ(to_string(Verdict::kOutOfOrder), "out-of-order");
}

TEST(FrameOrder, SourcesAreOrderedApartAndBoundedInNumber) {
  FrameOrder order;
  EXPECT_EQ(order.check("a", 5, 5000), Verdict::kNew);
  EXPECT_EQ(order.check("b", 1, 1000), Verdict::kNew);  // older than a's, but another source
  EXPECT_EQ(order.check("a", 6, 4000), Verdict::kOutOfOrder);
  for (int i = 0; i < 200; ++i) order.check("id" + std::to_string(i), 1, 100 + i);
  // Past the bound the newcomers share one entry: their frames are ordered together.
  EXPECT_EQ(order.check("another", 1, 50), Verdict::kOutOfOrder);
  EXPECT_EQ(order.check("a", 7, 6000), Verdict::kNew);  // known sources keep their own
}

}  // namespace
}  // namespace arphys::msg
