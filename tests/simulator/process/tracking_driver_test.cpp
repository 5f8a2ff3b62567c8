// How tracked poses drive a kinematic body: smooth, one frame late, never faster than a
// hand moves a real object whatever the tracking does, and after a lost track no faster
// than twice the object's own speed.
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

// A box pushed at 0.25 m/s is lost for 0.3 s and re-acquired 83 mm on: the body
// catches up at twice the box's own speed (0.5 m/s), not at the hand's 1.5 m/s, which
// threw the bunny it pushed at 7x. The frames that come meanwhile are headed for from
// where the body is (queued behind the re-acquired pose, they were run through at the
// hand's speed again), and it is back on the live poses, one frame late, after about
// as long as the gap lasted.
TEST(TrackingDriver, ReacquiredTrackCatchesUpAtTwiceItsOwnSpeed) {
  TrackingDriver d(TrackingPolicy::kDelay);
  const double v = 0.25, frame = 1 / 30.0;
  for (int k = 0; k <= 60; ++k) {
    const double t = k * frame;
    if (t >= 0.5 - 1e-9 && t < 0.8 - 1e-9) {
      d.on_lost(t);
    } else {
      d.on_pose(t, at_x(v * t), t);
    }
  }
  const auto [speed, rate] = fastest(d, 0.4, 2.0);
  EXPECT_LE(speed, 2 * v + 1e-6);
  EXPECT_GT(speed, 2 * v - 1e-6);
  EXPECT_NEAR(d.trajectory().pose_at(1.25).translation().x(), v * (1.25 - frame), 1e-9);  // caught up
  EXPECT_GT(d.trajectory().pose_at(1.0).translation().x(), v * 0.5);                     // moving on, not crawling
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
  // It heads back as soon as the next frame comes: it turns for one frame, not all the
  // way to the flipped pose (a quarter second) and back.
  double widest_rad = 0;
  for (double t = 0.3; t < 1.0; t += 1e-3) widest_rad = std::max(widest_rad, Eigen::AngleAxisd(d.trajectory().pose_at(t).linear()).angle());
  EXPECT_LT(widest_rad, 2 * M_PI / 30 + 1e-6);
  EXPECT_NEAR(Eigen::AngleAxisd(d.trajectory().pose_at(1.0).linear()).angle(), 0.0, 1e-9);
}

TEST(TrackingDriver, CatchUpFactorBelowOneIsRefused) {
  DriverLimits limits;
  limits.catch_up_factor = 0.5;
  EXPECT_THROW(TrackingDriver(TrackingPolicy::kDelay, limits), std::invalid_argument);
}

TEST(TrackingDriver, NonPositiveLimitsAreRefused) {
  DriverLimits limits;
  limits.max_speed_m_s = 0;
  try {
    TrackingDriver driver(TrackingPolicy::kDelay, limits);
    FAIL() << "accepted a zero speed limit";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_speed_m_s"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arphys::sim
