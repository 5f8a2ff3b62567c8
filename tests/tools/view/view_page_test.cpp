// The page of arphys-view in headless Chromium during a launched main job (arphys-launch
// --view), shot once it says it has drawn (tools/view/web/screenshot_page.mjs): the screenshot shows the overlay stream
// (the camera's picture, not a blank box) and the 3D world with the virtual bunnies on the tracked table, checked by
// pixels.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>

#include "tests/support/spawn_process.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7982?ttl=0";  // a port of its own
constexpr int kPort = 18772;

// Waits up to timeout_s for a process; kills it when it overruns. True when it exited with 0.
bool finished_ok(pid_t pid, double timeout_s) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > until) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

TEST(ViewPage, AScreenshotDuringTheMainJobShowsTheOverlayAndTheBodies) {
  const std::string dir = ::testing::TempDir() + "view_page_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  const pid_t launch = arphys::testing::spawn_process({std::string(ARPHYS_BINARY_DIR) + "/tools/launch/arphys-launch",
                                                       "--build", ARPHYS_BINARY_DIR, "--duration", "30", "--lcm-url",
                                                       kUrl, "--view", std::to_string(kPort)});
  ASSERT_GT(launch, 0);
  std::this_thread::sleep_for(std::chrono::seconds(5));  // running, bunnies spawned and fallen
  const std::string png = dir + "/page.png";
  // Chromium, driven by puppeteer-core, shoots once the page has shown overlay frames and bodies.
  const pid_t browser =
      arphys::testing::spawn_process({"node", std::string(ARPHYS_SOURCE_DIR) + "/tools/view/web/screenshot_page.mjs",
                                      "http://127.0.0.1:" + std::to_string(kPort) + "/", png, "40"});
  const bool shot = finished_ok(browser, 90);
  arphys::testing::stop_process(launch);
  ASSERT_TRUE(shot) << "chromium did not take the screenshot";
  const cv::Mat page = cv::imread(png, cv::IMREAD_COLOR);
  ASSERT_EQ(page.cols, 1300);
  // The overlay (the page's 640x480 image at 6,6): the camera's picture, bright and varied.
  cv::Scalar mean, stddev;
  cv::meanStdDev(page(cv::Rect(6, 6, 640, 480)), mean, stddev);
  EXPECT_GT(mean[0] + mean[1] + mean[2], 3 * 60.0) << "overlay missing (black)";
  EXPECT_GT(stddev[1], 20.0) << "overlay uniform";
  // The 3D view (right of it): bunnies (warm beige, red above blue) on the table (blue-grey).
  const cv::Mat world = page(cv::Rect(652, 6, 640, 480));
  int bunny = 0, table = 0;
  for (int y = 0; y < world.rows; ++y)
    for (int x = 0; x < world.cols; ++x) {
      const cv::Vec3b bgr = world.at<cv::Vec3b>(y, x);
      if (bgr[2] > 150 && bgr[2] > bgr[0] + 25) ++bunny;
      if (bgr[0] > bgr[2] + 15 && bgr[0] > 70) ++table;
    }
  EXPECT_GT(bunny, 300) << "no bunnies drawn";
  EXPECT_GT(table, 20000) << "no table drawn";
}

}  // namespace
