// How tracked poses drive a kinematic body: smooth, one frame late, and never faster
// than a hand moves a real object, whatever the tracking does.
#include "simulator/process/tracking_driver.hpp"

#include <gtest/gtest.h>

namespace arphys::sim {
namespace {

geometry::Pose at_x(double x) { return geometry::translation_pose({x, 0, 0}); }

// Largest speed (m/s) and rate (rad/s) of the body over [t0, t1], sampled every 1 ms.
std::pair<double, double> fastest(const TrackingDriver& d, double t0, double t1) {
  double speed = 0, rate = 0;
  for (double t = t0; t < t1; t += 1e-3) {
    const geometry::Pose a = d.trajectory().pose_at(t), b = d.trajectory().pose_at(t + 1e-3);
    speed = std::max(speed, (b.translation() - a.translation()).norm() / 1e-3);
    rate = std::max(rate, Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / 1e-3);
  }
  return {speed, rate};
}

TEST(TrackingDriver, DelayPolicyReachesEachPoseOneFrameLate) {
  TrackingDriver d(TrackingPolicy::kDelay);
  for (int k = 0; k <= 30; ++k) d.on_pose(k / 30.0, at_x(0.01 * k), k / 30.0);  // 0.3 m/s
  EXPECT_NEAR(d.trajectory().pose_at(20 / 30.0 + 1 / 30.0).translation().x(), 0.20, 1e-9);
  EXPECT_NEAR(fastest(d, 0.1, 1.0).first, 0.3, 1e-6);
}

// Re-acquired 0.3 m further on after a loss: before the speed limit the body crossed
// the gap in one frame (9 m/s) and threw a virtual bunny at 14 m/s; now at 1.5 m/s.
TEST(TrackingDriver, ReacquiredTrackIsReachedAtAHandsSpeed) {
  TrackingDriver d(TrackingPolicy::kDelay);
  for (int k = 0; k <= 10; ++k) d.on_pose(k / 30.0, at_x(0.01 * k), k / 30.0);
  d.on_lost(0.4);
  d.on_pose(0.7, at_x(0.4), 0.7);
  const auto [speed, rate] = fastest(d, 0.4, 1.2);
  EXPECT_LE(speed, 1.5 + 1e-6);
  EXPECT_NEAR(d.trajectory().pose_at(0.7 + 0.3 / 1.5 + 1e-6).translation().x(), 0.4, 1e-6);  // arrived, no later
}

// One frame reports the marker's other pose (flipped 90 degrees): the body turns no
// faster than one turn a second, and back when the next frame is right again.
TEST(TrackingDriver, FlippedPoseTurnsTheBodyNoFasterThanTheLimit) {
  TrackingDriver d(TrackingPolicy::kDelay);
  for (int k = 0; k <= 12; ++k) {
    geometry::Pose X = at_x(0);
    if (k == 10) X.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    d.on_pose(k / 30.0, X, k / 30.0);
  }
  const auto [speed, rate] = fastest(d, 0.3, 1.0);
  EXPECT_LE(rate, 2 * M_PI + 1e-6);
  EXPECT_GT(rate, 0.5 * 2 * M_PI);  // it does follow (the filter, not the driver, rejects flips)
}

TEST(TrackingDriver, NonPositiveLimitsAreRefused) {
  EXPECT_THROW(TrackingDriver(TrackingPolicy::kDelay, 1.0 / 30, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::sim
