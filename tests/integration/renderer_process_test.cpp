// The renderer as a real process on real LCM multicast: camera frames and world states
// in; overlays, render statuses and heartbeats out. A frame is drawn with the world state
// computed from it (exact), else the nearest earlier one, else with nothing virtual; bad
// frames and unknown models are counted, never fatal.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "arphys/image_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "tests/support/image_messages.hpp"
#include "tests/support/spawn_process.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7994?ttl=0";

arphys::image_t jpeg_frame(const cv::Mat& grey, int64_t utime, int64_t seq) {
  return arphys::testing::jpeg_image(grey, utime, seq);
}

arphys::body_state_t body(const std::string& id, const std::string& model, const Eigen::Vector3d& p) {
  arphys::body_state_t b{};
  b.body_id = id;
  b.model = model;
  b.role = arphys::body_state_t::ROLE_VIRTUAL;
  b.motion = arphys::body_state_t::MOTION_DYNAMIC;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();  // the bunny mesh is y-up
  X.translation() = p;
  b.X_WB = arphys::msg::to_message(X);
  return b;
}

// Pixels of the upper image (above the status text) that differ by more than 40 levels.
int changed_pixels(const arphys::image_t& overlay, const cv::Mat& grey) {
  cv::Mat decoded = cv::imdecode(overlay.data, cv::IMREAD_GRAYSCALE);
  if (decoded.size() != grey.size()) return -1;
  cv::Mat difference;
  cv::absdiff(decoded, grey, difference);
  return cv::countNonZero(difference(cv::Rect(0, 0, grey.cols, grey.rows - 40)) > 40);
}

TEST(RendererProcess, MatchesWorldStatesToFramesAndCountsBadInput) {
  {
    lcm::LCM probe(kUrl);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  arphys::msg::Bus bus(kUrl);
  std::vector<arphys::render_status_t> statuses;
  std::vector<arphys::image_t> overlays;
  std::vector<arphys::process_status_t> heartbeats;
  bus.subscribe<arphys::render_status_t>("ARPHYS_RENDER_STATUS", [&](const arphys::render_status_t& m,
                                                                     const lcm::ReceiveBuffer&, const std::string&) {
    statuses.push_back(m);
  });
  bus.subscribe<arphys::image_t>("ARPHYS_OVERLAY_IMAGE", [&](const arphys::image_t& m, const lcm::ReceiveBuffer&,
                                                            const std::string&) { overlays.push_back(m); });
  bus.subscribe<arphys::process_status_t>("ARPHYS_STATUS", [&](const arphys::process_status_t& m,
                                                               const lcm::ReceiveBuffer&, const std::string&) {
    if (m.name == "renderer") heartbeats.push_back(m);
  });
  const pid_t renderer = arphys::testing::spawn_process(
      {std::string(ARPHYS_BINARY_DIR) + "/renderer/app/renderer", "--scene",
       std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunny_box_table.yaml", "--lcm-url", kUrl, "--overlay-lcm",
       "--duration", "20"});
  ASSERT_GT(renderer, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  auto wait = [&](int ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) bus.handle_timeout_ms(10);
  };
  const cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(90));
  const int64_t t0 = arphys::msg::now_utime();

  bus.publish("ARPHYS_CAMERA_IMAGE", jpeg_frame(grey, t0, 0));  // no world state yet
  wait(400);
  arphys::world_state_t state{};
  state.utime = t0 + 33333;
  state.seq = 1;
  state.bodies = {body("bunny#0", "bunny", {0, 0, 0.05}), body("ghost#0", "ghost", {0, 0, 0.1})};
  state.num_bodies = 2;
  state.step_end_utime = t0 + 40000;
  bus.publish("ARPHYS_WORLD_STATE", state);
  wait(100);
  // A copy of it (re-sent, replayed), this time with no bunny: refused, so frame 1 still
  // gets the original.
  arphys::world_state_t copy = state;
  copy.bodies.resize(1);
  copy.bodies[0] = body("bunny#0", "bunny", {0, 0, 5.0});
  copy.num_bodies = 1;
  bus.publish("ARPHYS_WORLD_STATE", copy);
  wait(200);
  bus.publish("ARPHYS_CAMERA_IMAGE", jpeg_frame(grey, t0 + 33333, 1));  // its own state: exact
  wait(400);
  bus.publish("ARPHYS_CAMERA_IMAGE", jpeg_frame(grey, t0 + 66666, 2));  // nearest earlier
  wait(400);
  arphys::image_t broken = jpeg_frame(grey, t0 + 99999, 3);
  broken.data.resize(40);
  broken.size = 40;
  bus.publish("ARPHYS_CAMERA_IMAGE", broken);
  wait(300);
  bus.publish("ARPHYS_CAMERA_IMAGE", jpeg_frame(cv::Mat(240, 320, CV_8UC1, cv::Scalar(90)), t0 + 133333, 4));
  wait(1500);
  arphys::testing::stop_process(renderer);

  ASSERT_EQ(statuses.size(), 3u);  // the broken and the small frame are not rendered
  EXPECT_EQ(statuses[0].world_state_match, arphys::render_status_t::MATCH_NONE);
  EXPECT_EQ(statuses[1].world_state_match, arphys::render_status_t::MATCH_EXACT);
  EXPECT_EQ(statuses[1].world_state_utime, t0 + 33333);
  EXPECT_EQ(statuses[2].world_state_match, arphys::render_status_t::MATCH_NEAREST_EARLIER);
  EXPECT_EQ(statuses[2].world_state_utime, t0 + 33333);
  for (const auto& s : statuses) EXPECT_GE(s.render_end_utime, s.render_start_utime);
  ASSERT_EQ(overlays.size(), 3u);
  EXPECT_LT(changed_pixels(overlays[0], grey), 50);    // camera frame only
  EXPECT_GT(changed_pixels(overlays[1], grey), 2000);  // the bunny drawn
  ASSERT_FALSE(heartbeats.empty());
  const auto& last = heartbeats.back();
  EXPECT_GE(last.decode_errors, 1);  // the broken JPEG
  EXPECT_GE(last.rejected, 3);       // the small frame, the unknown model, the copied state
  EXPECT_EQ(arphys::msg::figure(last, "duplicate world state").value_or(0), 1);
}

}  // namespace
