// The tracker as a real process on real LCM multicast: frames in on an image channel,
// detections and object poses out; the detector swapped at run time by a
// tracker_control_t message; a second tracker process taking over from a first that
// stopped; undecodable images counted in the heartbeat.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "arphys/image_t.hpp"
#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "tests/support/image_messages.hpp"
#include "tests/support/spawn_process.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7993?ttl=0";
const std::string kImages = "TRACKER_TEST_IMAGES";
const std::string kTracker = std::string(ARPHYS_BINARY_DIR) + "/tracker/app/tracker";
const std::string kCamera = std::string(ARPHYS_SOURCE_DIR) + "/configs/cameras/synthetic_640x480.yaml";

arphys::image_t image_message(const cv::Mat& grey, int64_t seq) {
  return arphys::testing::jpeg_image(grey, arphys::msg::now_utime(), seq);
}

pid_t start_tracker(const std::string& impl, const std::string& name) {
  return arphys::testing::spawn_process({kTracker, "--camera", kCamera, "--source", "lcm:" + kImages, "--lcm-url", kUrl,
                                         "--marker-size", "0.08", "--impl", impl, "--name", name, "--duration", "30"});
}

TEST(TrackerProcess, SwapsDetectorLiveAndHandsOverToASecondProcess) {
  {
    lcm::LCM probe(kUrl);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  arphys::msg::Bus bus(kUrl);
  std::vector<arphys::marker_detections_t> detections;
  std::vector<arphys::process_status_t> statuses;
  bus.subscribe<arphys::marker_detections_t>(
      "ARPHYS_MARKERS", [&](const arphys::marker_detections_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        detections.push_back(m);
      });
  bus.subscribe<arphys::process_status_t>(
      "ARPHYS_STATUS", [&](const arphys::process_status_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        statuses.push_back(m);
      });
  const auto camera = arphys::tracking::CameraModel::from_config(arphys::config::load_camera(kCamera));
  const cv::Mat background = arphys::tracking::clutter_background(640, 480, 8);
  const cv::Mat frame = arphys::tracking::render_markers(
      camera, {{"tag36h11", 6, 0.08, arphys::tracking::marker_pose_at(camera, 300, 220, 0.6, 0.4, 0.5, 0.1)}}, background);
  int64_t seq = 0;
  // Publishes frames at ~20 Hz for `seconds`, handling replies in between.
  auto feed = [&](double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      bus.publish(kImages, image_message(frame, seq++));
      const auto next = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
      while (std::chrono::steady_clock::now() < next) bus.handle_timeout_ms(10);
    }
  };
  auto count_from = [&](size_t first, const std::string& impl) {
    int n = 0;
    for (size_t i = first; i < detections.size(); ++i) {
      if (detections[i].tracker_implementation.rfind(impl, 0) == 0 && detections[i].num_markers == 1 &&
          detections[i].markers[0].id == 6) {
        ++n;
      }
    }
    return n;
  };

  pid_t first = start_tracker("apriltag", "tracker-a");
  ASSERT_GT(first, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  feed(1.5);
  EXPECT_GE(count_from(0, "apriltag"), 10);

  // An undecodable JPEG is counted, not fatal.
  arphys::image_t bad = image_message(frame, seq++);
  bad.pixel_format = arphys::image_t::PIXEL_FORMAT_JPEG;
  bad.data.assign(100, 7);
  bad.size = 100;
  bus.publish(kImages, bad);

  // Live swap to ArUco; a request for a bad parameter is refused without effect.
  arphys::tracker_control_t control{};
  control.utime = arphys::msg::now_utime();
  control.target = "tracker-a";
  control.implementation = "aruco";
  bus.publish("ARPHYS_TRACKER_CONTROL", control);
  feed(1.5);
  const size_t after_swap = detections.size();
  arphys::tracker_control_t bad_control{};
  bad_control.param_names = {"no_such_parameter"};
  bad_control.param_values = {"1"};
  bad_control.num_params = 1;
  bus.publish("ARPHYS_TRACKER_CONTROL", bad_control);
  feed(1.5);
  EXPECT_GE(count_from(after_swap, "aruco"), 10);
  EXPECT_EQ(count_from(after_swap, "apriltag"), 0);
  bool saw_counts = false;
  for (const auto& s : statuses) {
    if (s.name != "tracker-a") continue;
    for (int i = 0; i < s.num_figures; ++i) {
      if (s.figure_names[i] == "detector_switches" && s.figure_values[i] == 1) {
        for (int j = 0; j < s.num_figures; ++j) {
          if (s.figure_names[j] == "rejected_controls" && s.figure_values[j] == 1 && s.decode_errors >= 1) saw_counts = true;
        }
      }
    }
  }
  EXPECT_TRUE(saw_counts) << "heartbeat should count the switch, the refused control and the bad image";

  // The first tracker stops; a second one (the other implementation) takes over.
  arphys::testing::stop_process(first);
  const size_t before_second = detections.size();
  pid_t second = start_tracker("apriltag", "tracker-b");
  ASSERT_GT(second, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  feed(1.5);
  arphys::testing::stop_process(second);
  EXPECT_GE(count_from(before_second, "apriltag"), 10);
}

}  // namespace
