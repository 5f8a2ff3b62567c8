// Camera calibration from a ChArUco board, against a camera whose intrinsics are known
// exactly: the board is rendered at varied poses (tracker/synthetic), and the calibration
// must give the camera back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/config_error.hpp"
#include "tracker/calibration/charuco_calibration.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace arphys::tracking {
namespace {

// Not the tracker tests' camera: fx != fy and an off-centre principal point, so an
// answer that assumed the usual values would show.
CameraModel true_camera() {
  CameraModel camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.K = cv::Matx33d(610, 0, 327.25, 0, 604, 231.5, 0, 0, 1);
  return camera;
}

CharucoBoardSpec board_spec() { return {}; }  // 7x5 squares of 3 cm, 2.2 cm markers, DICT_5X5_100

constexpr int kSquarePx = 60, kMarginPx = 30;  // the board as drawn for rendering

// Where the board's pose puts each inner corner in the image (ids along x from the
// drawn board's top-left), for the corners' own accuracy.
cv::Point2d true_corner_px(const CameraModel& camera, const geometry::Pose& X_CB, int id) {
  const CharucoBoardSpec spec = board_spec();
  const int columns = spec.squares_x * kSquarePx + 2 * kMarginPx, rows = spec.squares_y * kSquarePx + 2 * kMarginPx;
  const double pixel_m = spec.square_size_m / kSquarePx;
  // In the drawn picture the corner lies between pixels, at (u, v) in OpenCV's convention.
  const double u = kMarginPx + (id % (spec.squares_x - 1) + 1) * kSquarePx - 0.5;
  const double v = kMarginPx + (id / (spec.squares_x - 1) + 1) * kSquarePx - 0.5;
  const Eigen::Vector3d p_C = X_CB * Eigen::Vector3d((u - 0.5 * (columns - 1)) * pixel_m, -(v - 0.5 * (rows - 1)) * pixel_m, 0);
  return {camera.K(0, 0) * p_C.x() / p_C.z() + camera.K(0, 2), camera.K(1, 1) * p_C.y() / p_C.z() + camera.K(1, 2)};
}

struct Picture {
  cv::Mat image;
  geometry::Pose X_CB;
};

// Pictures of the board as a person takes them for a calibration: at 0.45-0.7 m, across
// the image (its centres over the middle 240 x 160 px, times `spread`), tilted 15-45
// degrees about varied axes.
std::vector<Picture> board_pictures(const CameraModel& camera, int count, double spread = 1.0) {
  const cv::Mat board = draw_charuco_board(board_spec(), kSquarePx, kMarginPx);
  const double width_m = board.cols * board_spec().square_size_m / kSquarePx;
  std::vector<Picture> pictures;
  for (int k = 0; k < count; ++k) {
    const double u = 320 + spread * 120 * (2 * ((k * 37) % 11) / 10.0 - 1);
    const double v = 240 + spread * 80 * (2 * ((k * 53) % 7) / 6.0 - 1);
    const double distance_m = 0.45 + 0.25 * ((k * 29) % 5) / 4.0;
    const double tilt_rad = (15 + 30 * ((k * 17) % 4) / 3.0) * M_PI / 180;
    const geometry::Pose X_CB = marker_pose_at(camera, u, v, distance_m, tilt_rad, 0.7 * k, 0.3 * std::sin(k));
    ImageEffects effects;
    effects.noise_sigma = 1.5;
    effects.seed = 100 + k;
    pictures.push_back({render_planar_image(camera, board, width_m, X_CB, clutter_background(640, 480, 7 + k), effects), X_CB});
  }
  return pictures;
}

std::vector<BoardView> detect_all(const std::vector<Picture>& pictures) {
  std::vector<BoardView> views;
  for (std::size_t k = 0; k < pictures.size(); ++k)
    if (auto view = detect_charuco_board(board_spec(), pictures[k].image)) {
      view->name = "view " + std::to_string(k);
      views.push_back(*view);
    }
  return views;
}

// The corners are where the board is, in OpenCV's pixel convention: OpenCV 4.6's own
// ChArUco corners are 0.5 px off in x and y (opencv#25539), which put a calibration's
// principal point 0.9 px off here.
TEST(CharucoCalibration, CornersLieWhereTheBoardIs) {
  const CameraModel camera = true_camera();
  const std::vector<Picture> pictures = board_pictures(camera, 6);
  cv::Point2d sum(0, 0);
  double worst_px = 0;
  int count = 0;
  for (const Picture& picture : pictures) {
    const auto view = detect_charuco_board(board_spec(), picture.image);
    ASSERT_TRUE(view.has_value());
    for (std::size_t k = 0; k < view->corners_px.size(); ++k) {
      const cv::Point2d error = cv::Point2d(view->corners_px[k]) - true_corner_px(camera, picture.X_CB, view->corner_ids[k]);
      sum += error;
      worst_px = std::max(worst_px, cv::norm(error));
      ++count;
    }
  }
  std::printf("%d corners: mean error (%.3f, %.3f) px, worst %.3f px\n", count, sum.x / count, sum.y / count, worst_px);
  EXPECT_LT(std::abs(sum.x / count), 0.03);
  EXPECT_LT(std::abs(sum.y / count), 0.03);
  EXPECT_LT(worst_px, 0.5);
}

TEST(CharucoCalibration, GivesTheCameraBackFromRenderedPictures) {
  const CameraModel camera = true_camera();
  const std::vector<BoardView> views = detect_all(board_pictures(camera, 14));
  ASSERT_GE(views.size(), 12u) << "the board was not found in most pictures";
  const int inner_corners = (board_spec().squares_x - 1) * (board_spec().squares_y - 1);
  for (const BoardView& view : views) EXPECT_LE(static_cast<int>(view.corners_px.size()), inner_corners);

  // The renderer's lens has no distortion: a pinhole model is the right one, and must
  // recover the focal lengths to 0.1 % and the principal point to 0.3 px.
  CalibrationOptions pinhole;
  pinhole.distortion = false;
  const CameraCalibration fit = calibrate_from_views(board_spec(), views, {640, 480}, pinhole);
  std::printf("pinhole fit from %d views: fx %.2f fy %.2f cx %.2f cy %.2f px (true 610 604 327.25 231.5), rms %.3f px, "
              "sigma fx %.2f cx %.2f cy %.2f px\n",
              fit.views, fit.camera.fx_px, fit.camera.fy_px, fit.camera.cx_px, fit.camera.cy_px, fit.rms_reprojection_px,
              fit.fx_sigma_px, fit.cx_sigma_px, fit.cy_sigma_px);
  EXPECT_NEAR(fit.camera.fx_px, 610, 0.001 * 610);
  EXPECT_NEAR(fit.camera.fy_px, 604, 0.001 * 604);
  EXPECT_NEAR(fit.camera.cx_px, 327.25, 0.3);
  EXPECT_NEAR(fit.camera.cy_px, 231.5, 0.3);
  EXPECT_LT(fit.rms_reprojection_px, 0.1);
  EXPECT_GT(fit.fx_sigma_px, 0);
  EXPECT_LT(fit.fx_sigma_px, 1.5);
  ASSERT_EQ(fit.view_rms_px.size(), views.size());
  for (const double d : fit.camera.distortion) EXPECT_EQ(d, 0.0);

  // With the default model (k1 k2 p1 p2, k3 held): the distortion it finds is small and
  // the focal length stays within 1 %.
  const CameraCalibration with_lens = calibrate_from_views(board_spec(), views, {640, 480});
  std::printf("with distortion: fx %.2f fy %.2f, k1 %.4f k2 %.4f p1 %.5f p2 %.5f, rms %.3f px\n",
              with_lens.camera.fx_px, with_lens.camera.fy_px, with_lens.camera.distortion[0],
              with_lens.camera.distortion[1], with_lens.camera.distortion[2], with_lens.camera.distortion[3],
              with_lens.rms_reprojection_px);
  EXPECT_NEAR(with_lens.camera.fx_px, 610, 0.01 * 610);
  EXPECT_LT(std::abs(with_lens.camera.distortion[0]), 0.05);
  EXPECT_EQ(with_lens.camera.distortion[4], 0.0);  // k3 held

  // Written and read back by the loader the tracker uses.
  const std::string path = (std::filesystem::temp_directory_path() / "arphys_calibration_test.yaml").string();
  write_camera_file(path, fit, "test-cam", board_spec());
  const config::CameraConfig loaded = config::load_camera(path);
  EXPECT_EQ(loaded.camera_id, "test-cam");
  EXPECT_EQ(loaded.width_px, 640);
  EXPECT_EQ(loaded.height_px, 480);
  EXPECT_NEAR(loaded.fx_px, fit.camera.fx_px, 1e-9);
  EXPECT_NEAR(loaded.cy_px, fit.camera.cy_px, 1e-9);
  EXPECT_EQ(loaded.distortion.size(), 5u);
  std::filesystem::remove(path);
}

// A webcam's barrel lens: the default model (k1 k2 p1 p2) finds it from pictures that
// reach towards the image's corners (where the lens shows), and a pinhole fit of the same
// pictures shows the misfit as its RMS error.
TEST(CharucoCalibration, FindsABarrelLens) {
  CameraModel camera = true_camera();
  camera.distortion = (cv::Mat_<double>(1, 5) << -0.28, 0.09, 0.0005, -0.0003, 0.0);
  const std::vector<BoardView> views = detect_all(board_pictures(camera, 20, 1.6));
  ASSERT_GE(views.size(), 16u);
  const CameraCalibration fit = calibrate_from_views(board_spec(), views, {640, 480});
  const std::vector<double>& d = fit.camera.distortion;
  std::printf("barrel lens from %d views: fx %.2f fy %.2f cx %.2f cy %.2f px, k1 %.4f k2 %.4f p1 %.5f p2 %.5f "
              "(true -0.28 0.09 0.0005 -0.0003), rms %.3f px\n",
              fit.views, fit.camera.fx_px, fit.camera.fy_px, fit.camera.cx_px, fit.camera.cy_px, d[0], d[1], d[2], d[3],
              fit.rms_reprojection_px);
  EXPECT_NEAR(d[0], -0.28, 0.02);
  EXPECT_NEAR(d[1], 0.09, 0.03);
  EXPECT_NEAR(d[2], 0.0005, 0.0005);
  EXPECT_NEAR(d[3], -0.0003, 0.0005);
  EXPECT_NEAR(fit.camera.fx_px, 610, 0.005 * 610);
  EXPECT_NEAR(fit.camera.cx_px, 327.25, 1.0);
  EXPECT_LT(fit.rms_reprojection_px, 0.15);
  CalibrationOptions pinhole;
  pinhole.distortion = false;
  const CameraCalibration misfit = calibrate_from_views(board_spec(), views, {640, 480}, pinhole);
  std::printf("the same as a pinhole: rms %.3f px\n", misfit.rms_reprojection_px);
  EXPECT_GT(misfit.rms_reprojection_px, 5 * fit.rms_reprojection_px);
}

TEST(CharucoCalibration, TooFewViewsAreRefusedByCount) {
  const std::vector<BoardView> views = detect_all(board_pictures(true_camera(), 3));
  ASSERT_EQ(views.size(), 3u);
  try {
    calibrate_from_views(board_spec(), views, {640, 480});
    FAIL() << "three views were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("3 views"), std::string::npos) << e.what();
  }
}

TEST(CharucoCalibration, APictureWithoutTheBoardHasNoView) {
  EXPECT_FALSE(detect_charuco_board(board_spec(), clutter_background(640, 480, 3)).has_value());
  EXPECT_FALSE(detect_charuco_board(board_spec(), cv::Mat()).has_value());
  // The board printed with another dictionary is not this board.
  CharucoBoardSpec other = board_spec();
  other.dictionary = "DICT_4X4_50";
  const std::vector<Picture> pictures = board_pictures(true_camera(), 1);
  EXPECT_TRUE(detect_charuco_board(board_spec(), pictures[0].image).has_value());
  EXPECT_FALSE(detect_charuco_board(other, pictures[0].image).has_value());
}

TEST(CharucoCalibration, ImpossibleBoardsAreRefusedNamingTheValue) {
  const auto refused = [](CharucoBoardSpec spec, const std::string& named) {
    try {
      check_board(spec);
      ADD_FAILURE() << "accepted a board that should name " << named;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
  };
  CharucoBoardSpec spec;
  spec.squares_x = 1;
  refused(spec, "1x5 squares");
  spec = {};
  spec.marker_size_m = 0.04;
  refused(spec, "marker_size_m = 0.04");
  spec = {};
  spec.square_size_m = -0.04;
  refused(spec, "square_size_m = -0.04");
  spec = {};
  spec.squares_x = spec.squares_y = 11;  // 60 markers
  spec.dictionary = "DICT_4X4_50";
  refused(spec, "has only 50");
  spec = {};
  spec.dictionary = "DICT_9X9_1";
  refused(spec, "DICT_9X9_1");
  EXPECT_NO_THROW(check_board(CharucoBoardSpec{}));
}

}  // namespace
}  // namespace arphys::tracking
