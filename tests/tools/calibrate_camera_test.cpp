// The arphys-calibrate-camera command, run as a real process on a folder of rendered
// pictures of its own board: the camera file it writes is the camera the pictures came
// from, and the tracker's loader reads it.
#include <gtest/gtest.h>

#include <unistd.h>

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
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace arphys::tracking {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

int run(const std::string& arguments, const std::filesystem::path& dir) {
  const std::string command = std::string(ARPHYS_BINARY_DIR) + "/tools/calibrate_camera/arphys-calibrate-camera " +
                              arguments + " > " + (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
  return WEXITSTATUS(std::system(command.c_str()));
}

TEST(CalibrateCameraCli, WritesTheCameraThePicturesCameFrom) {
  const auto dir = std::filesystem::temp_directory_path() / ("calibrate_camera_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "pictures");
  // The board as the command draws it for printing (3 cm squares at 300 dpi: 354 px).
  ASSERT_EQ(run("--write-board " + (dir / "board.png").string(), dir), 0) << read_file(dir / "err.txt");
  const cv::Mat board = cv::imread((dir / "board.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(board.empty());
  EXPECT_NE(read_file(dir / "out.txt").find("24.0 x 18.0 cm"), std::string::npos) << read_file(dir / "out.txt");
  const double width_m = 0.03 * board.cols / 354.0;

  CameraModel camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.K = cv::Matx33d(585, 0, 311.5, 0, 588, 247.0, 0, 0, 1);
  for (int k = 0; k < 12; ++k) {
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

}  // namespace
}  // namespace arphys::tracking
