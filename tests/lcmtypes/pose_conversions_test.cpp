#include "lcmtypes/msg/pose_conversions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "simulator/geometry/pose.hpp"

namespace arphys::msg {
namespace {

TEST(PoseConversions, RoundTripIsExactToRounding) {
  const geometry::Pose X = geometry::translation_pose({0.1, -2.5, 3}) * geometry::rotation_pose({1, -1, 2}, 2.9);
  const arphys::pose_t m = to_message(X);
  EXPECT_GE(m.orientation_wxyz[0], -1.0);
  const geometry::Pose back = from_message(m);
  EXPECT_LT((back.matrix() - X.matrix()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PoseConversions, RejectsNaNAndNonUnitQuaternionsNamingTheField) {
  arphys::pose_t m = to_message(geometry::Pose::Identity());
  m.position_m[1] = std::numeric_limits<double>::quiet_NaN();
  try {
    from_message(m, "X_WB of body 'box'");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("X_WB of body 'box': position_m[1] is nan"), std::string::npos) << e.what();
  }
  m = to_message(geometry::Pose::Identity());
  m.orientation_wxyz[0] = 2.0;
  EXPECT_NE(pose_problem(m).find("norm 2"), std::string::npos) << pose_problem(m);
  m.orientation_wxyz[0] = std::numeric_limits<double>::infinity();
  EXPECT_NE(pose_problem(m).find("orientation_wxyz[0] is inf"), std::string::npos);
  m.orientation_wxyz[0] = 1.0 + 5e-7;  // within tolerance: accepted and renormalised
  EXPECT_TRUE(pose_problem(m).empty());
  EXPECT_NEAR(Eigen::Quaterniond(from_message(m).linear()).norm(), 1.0, 1e-15);
}

}  // namespace
}  // namespace arphys::msg
