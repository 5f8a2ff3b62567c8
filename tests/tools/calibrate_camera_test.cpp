// The arphys-calibrate-camera command, run as a real process on a folder of rendered
// pictures of its own board: the camera file it writes is the camera the pictures came
// from, and the tracker's loader reads it.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <thread>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "configs/loader/camera_config.hpp"
#include "tests/support/read_file.hpp"
#include "tests/support/spawn_process.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace arphys::tracking {
namespace {

using arphys::testing::read_file;

int run(const std::string& arguments, const std::filesystem::path& dir) {
  const std::string command = std::string(ARPHYS_BINARY_DIR) + "/tools/calibrate_camera/arphys-calibrate-camera " +
                              arguments + " > " + (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
  return WEXITSTATUS(std::system(command.c_str()));
}

// Draws the board with the command (3 cm squares at 300 dpi: 354 px) and writes
// 12 x `copies` pictures of it, as a 585/588 px camera takes them, into dir/pictures.
void write_pictures(const std::filesystem::path& dir, int copies = 1) {
  std::filesystem::create_directories(dir / "pictures");
  ASSERT_EQ(run("--write-board " + (dir / "board.png").string(), dir), 0) << read_file(dir / "err.txt");
  const cv::Mat board = cv::imread((dir / "board.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(board.empty());
  EXPECT_NE(read_file(dir / "out.txt").find("24.0 x 18.0 cm"), std::string::npos) << read_file(dir / "out.txt");
  const double width_m = 0.03 * board.cols / 354.0;
  CameraModel camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.K = cv::Matx33d(585, 0, 311.5, 0, 588, 247.0, 0, 0, 1);
  for (int k = 0; k < 12 * copies; ++k) {
    const double u = 180 + 280 * ((k * 5) % 6) / 5.0, v = 150 + 180 * ((k * 3) % 4) / 3.0;
    const geometry::Pose X_CB =
        marker_pose_at(camera, u, v, 0.4 + 0.05 * (k % 4), (18 + 8 * (k % 4)) * M_PI / 180, 0.9 * k, 0.2 * k);
    ImageEffects effects;
    effects.noise_sigma = 1.0;
    effects.seed = k + 1;
    char name[32];
    std::snprintf(name, sizeof name, "view%02d.png", k);
    cv::imwrite((dir / "pictures" / name).string(), render_planar_image(camera, board, width_m, X_CB, {}, effects));
  }
}

TEST(CalibrateCameraCli, WritesTheCameraThePicturesCameFrom) {
  const auto dir = std::filesystem::temp_directory_path() / ("calibrate_camera_test_" + std::to_string(::getpid()));
  write_pictures(dir);
  // A picture without the board among them is passed over.
  cv::imwrite((dir / "pictures" / "view99.png").string(), clutter_background(640, 480, 5));

  const std::string out = (dir / "camera.yaml").string();
  ASSERT_EQ(run("--source " + (dir / "pictures").string() + " --out " + out + " --camera-id bench-cam --no-distortion", dir), 0)
      << read_file(dir / "err.txt");
  std::printf("%s", read_file(dir / "out.txt").c_str());
  EXPECT_NE(read_file(dir / "err.txt").find("13 pictures read, the board found in 12, 12 views kept"), std::string::npos)
      << read_file(dir / "err.txt");
  const config::CameraConfig written = config::load_camera(out);
  EXPECT_EQ(written.camera_id, "bench-cam");
  EXPECT_NEAR(written.fx_px, 585, 0.003 * 585);
  EXPECT_NEAR(written.fy_px, 588, 0.003 * 588);
  EXPECT_NEAR(written.cx_px, 311.5, 0.5);
  EXPECT_NEAR(written.cy_px, 247.0, 0.5);
  EXPECT_NE(read_file(out).find("ChArUco board 7x5 squares of 0.03 m"), std::string::npos);

  // A video of the same pictures, each held for 10 frames: every 5th frame is tried and a
  // view that has not moved from the last one kept adds nothing, so each picture gives one
  // view (the stills of a folder are all kept).
  {
    cv::VideoWriter video((dir / "sweep.avi").string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30, {640, 480}, false);
    ASSERT_TRUE(video.isOpened());
    for (int k = 0; k < 12; ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "view%02d.png", k);
      const cv::Mat picture = cv::imread((dir / "pictures" / name).string(), cv::IMREAD_GRAYSCALE);
      for (int repeat = 0; repeat < 10; ++repeat) video.write(picture);
    }
  }
  ASSERT_EQ(run("--source " + (dir / "sweep.avi").string() + " --out " + out + " --no-distortion", dir), 0)
      << read_file(dir / "err.txt");
  EXPECT_NE(read_file(dir / "err.txt").find("120 pictures read, the board found in 24, 12 views kept"), std::string::npos)
      << read_file(dir / "err.txt");
  EXPECT_NEAR(config::load_camera(out).fx_px, 585, 0.003 * 585);

  // Pictures of another board (other dictionary): no views, a clear refusal, no file.
  std::filesystem::remove(out);
  EXPECT_EQ(run("--source " + (dir / "pictures").string() + " --out " + out + " --dictionary DICT_6X6_250", dir), 1);
  EXPECT_NE(read_file(dir / "err.txt").find("0 views of the board, expected at least 4"), std::string::npos)
      << read_file(dir / "err.txt");
  EXPECT_FALSE(std::filesystem::exists(out));
  // A board that cannot exist is named.
  EXPECT_EQ(run("--source " + (dir / "pictures").string() + " --out " + out + " --square-size 0.02 --marker-size 0.025", dir), 1);
  EXPECT_NE(read_file(dir / "err.txt").find("marker_size_m = 0.025"), std::string::npos) << read_file(dir / "err.txt");
  // A missing source is named.
  EXPECT_EQ(run("--source " + (dir / "nowhere").string() + " --out " + out, dir), 1);
  EXPECT_NE(read_file(dir / "err.txt").find("nowhere"), std::string::npos) << read_file(dir / "err.txt");
  std::filesystem::remove_all(dir);
}

// Ctrl-C while pictures are still coming (a live camera runs until --max-views): the
// views so far are calibrated and written, exit 0.
TEST(CalibrateCameraCli, CtrlCCalibratesFromTheViewsSoFar) {
  const auto dir = std::filesystem::temp_directory_path() / ("calibrate_camera_ctrl_c_" + std::to_string(::getpid()));
  write_pictures(dir, 10);  // 120 pictures: seconds of work
  const std::string out = (dir / "camera.yaml").string(), err = (dir / "progress.txt").string();
  const pid_t pid = arphys::testing::spawn_process(
      {"sh", "-c", "exec " + std::string(ARPHYS_BINARY_DIR) + "/tools/calibrate_camera/arphys-calibrate-camera --source " +
                       (dir / "pictures").string() + " --out " + out + " --max-views 120 --no-distortion 2> " + err});
  ASSERT_GT(pid, 0);
  // Interrupted once it has kept 6 views.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (read_file(err).find("view 6 of") == std::string::npos && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  const std::string progress = read_file(err);
  ASSERT_TRUE(WIFEXITED(status)) << progress;
  EXPECT_EQ(WEXITSTATUS(status), 0) << progress;
  EXPECT_NE(progress.find("stopped: "), std::string::npos) << progress;
  EXPECT_EQ(progress.find("view 120 of"), std::string::npos) << "it ran to the end: " << progress;
  EXPECT_NEAR(config::load_camera(out).fx_px, 585, 0.01 * 585);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace arphys::tracking
