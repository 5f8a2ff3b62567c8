// The overlay registration error of arphys-launch: the drawn pose against the truth,
// in pixels, for the frame and world state the renderer names.
#include "tools/launch/registration_report.hpp"

#include <gtest/gtest.h>

#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::tools {
namespace {

arphys::ground_truth_t truth(int64_t utime, const Eigen::Vector3d& box_W) {
  arphys::ground_truth_t m{};
  m.utime = utime;
  m.X_WC = msg::to_message(Eigen::Isometry3d::Identity());  // camera at the origin, looking down +z
  m.num_objects = 1;
  m.object_ids = {"box"};
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = box_W;
  m.X_WO = {msg::to_message(X)};
  return m;
}

arphys::world_state_t world(double sim_time_s, const Eigen::Vector3d& box_W) {
  arphys::world_state_t m{};
  m.sim_time_s = sim_time_s;
  arphys::body_state_t b{};
  b.body_id = "box";
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = box_W;
  b.X_WB = msg::to_message(X);
  m.bodies = {b};
  m.num_bodies = 1;
  return m;
}

arphys::render_status_t drawn(int64_t utime, double sim_time_s) {
  arphys::render_status_t m{};
  m.utime = utime;
  m.world_state_sim_time_s = sim_time_s;
  m.world_state_match = arphys::render_status_t::MATCH_NEAREST_EARLIER;
  return m;
}

// 640x480, f = 500 px, centred.
config::CameraConfig camera_500px() {
  config::CameraConfig camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.fx_px = camera.fy_px = 500;
  camera.cx_px = 320;
  camera.cy_px = 240;
  return camera;
}

TEST(RegistrationReport, PixelsBetweenDrawnAndTrueObject) {
  const config::CameraConfig camera = camera_500px();
  RegistrationReport report(camera, "box", {{0, 0, 0}, {0.05, 0, 0}});
  // Frame 1: drawn where it is. Frame 2: drawn 1 cm off sideways at 1 m: 5 px. A
  // world state the renderer did not use (sim time 0.3) changes nothing.
  report.on_ground_truth(truth(1000, {0, 0, 1}));
  report.on_ground_truth(truth(2000, {0.01, 0, 1}));
  report.on_world_state(world(0.1, {0, 0, 1}));
  report.on_world_state(world(0.2, {0, 0, 1}));
  report.on_world_state(world(0.3, {0.01, 0, 1}));
  report.on_render_status(drawn(1000, 0.1));
  report.on_render_status(drawn(2000, 0.2));
  report.on_render_status(drawn(3000, 0.2));  // no truth for this frame: not measured
  ASSERT_EQ(report.errors_px().size(), 2u);
  EXPECT_NEAR(report.errors_px()[0], 0.0, 1e-9);
  EXPECT_NEAR(report.errors_px()[1], 5.0, 1e-9);
  EXPECT_NEAR(report.to_json()["max_px"].get<double>(), 5.0, 1e-9);
}

// Through a lens the same offset covers the pixels the lens shows it over: near the
// image's edge a barrel lens squeezes it (k1 -0.3 at 0.4 of the focal length off axis:
// 1 + 3 k1 r^2 = 0.856 of the pinhole's 5 px, to first order).
TEST(RegistrationReport, PixelsAreCountedThroughTheLens) {
  config::CameraConfig camera = camera_500px();
  camera.distortion = {-0.3, 0, 0, 0, 0};
  RegistrationReport report(camera, "box", {{0, 0, 0}});
  report.on_ground_truth(truth(1000, {0.4, 0, 1}));
  report.on_world_state(world(0.1, {0.41, 0, 1}));
  report.on_render_status(drawn(1000, 0.1));
  ASSERT_EQ(report.errors_px().size(), 1u);
  // Exactly: 500 (x (1 + k1 x^2)) between x = 0.4 and 0.41.
  const auto distorted = [](double x) { return 500 * x * (1 - 0.3 * x * x); };
  EXPECT_NEAR(report.errors_px()[0], distorted(0.41) - distorted(0.4), 1e-9);
  EXPECT_NEAR(report.errors_px()[0], 5.0 * (1 - 3 * 0.3 * 0.16), 0.05);
}

}  // namespace
}  // namespace arphys::tools
