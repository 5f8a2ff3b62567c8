#include "tools/launch/run_end.hpp"

#include <gtest/gtest.h>

namespace arphys::launch {
namespace {

TEST(RunEnd, SyntheticRunSettlesOnceFramesStopAfterTheCamera) {
  RunEnd end(10, true);
  EXPECT_FALSE(end.over(9.0, false, 100));
  EXPECT_FALSE(end.over(10.0, true, 110));  // camera done; frames still coming
  EXPECT_FALSE(end.over(10.4, true, 120));
  EXPECT_FALSE(end.over(10.8, true, 120));  // quiet for 0.4 s
  EXPECT_TRUE(end.over(11.0, true, 120));   // quiet for 0.6 s
  EXPECT_EQ(end.why(), "settled");
  EXPECT_NEAR(end.drain_s(), 1.0, 1e-12);
}

TEST(RunEnd, BusyPipelineEndsAtTheDrainLimitAndALateCameraAtItsLimit) {
  RunEnd busy(10, true);
  int64_t frames = 0;
  double t = 10;
  EXPECT_FALSE(busy.over(t, true, ++frames));
  while (!busy.over(t += 0.1, true, ++frames)) ASSERT_LT(t, 20);
  EXPECT_EQ(busy.why(), "drain_limit");
  EXPECT_GT(busy.drain_s(), RunEnd::kDrainS);
  RunEnd late(10, true);
  EXPECT_FALSE(late.over(10 + RunEnd::kCameraLateLimitS - 0.1, false, 5));
  EXPECT_TRUE(late.over(10 + RunEnd::kCameraLateLimitS + 0.1, false, 6));
  EXPECT_EQ(late.why(), "camera_late");
}

TEST(RunEnd, OtherSourcesRunTheirDurationAndTheDrain) {
  RunEnd end(5, false);
  EXPECT_FALSE(end.over(5 + RunEnd::kDrainS - 0.01, true, 0));
  EXPECT_TRUE(end.over(5 + RunEnd::kDrainS + 0.01, true, 0));
  EXPECT_EQ(end.why(), "duration");
}

}  // namespace
}  // namespace arphys::launch
