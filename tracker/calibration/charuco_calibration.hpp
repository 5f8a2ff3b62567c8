#pragma once
// Camera calibration from pictures of a printed ChArUco board (a chessboard whose white
// squares carry ArUco markers): the tracker needs a calibrated camera, and a ChArUco
// board is found even when it is partly out of view or partly covered, where a plain
// chessboard must be seen whole. OpenCV (aruco contrib) does the detection and the
// calibration; this adds the checks and the reporting a user needs to trust the result.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "configs/loader/camera_config.hpp"

namespace arphys::tracking {

struct CharucoBoardSpec {
  int squares_x = 7;  // squares along the board's width
  int squares_y = 5;  // and along its height
  double square_size_m = 0.03;  // side of a chessboard square, as printed (7x5 of 3 cm fit A4 or Letter)
  double marker_size_m = 0.022;  // side of a marker inside a white square
  std::string dictionary = "DICT_5X5_100";  // OpenCV ArUco dictionary name
};

// Throws std::invalid_argument naming the value when the board cannot exist: fewer than
// 2x2 squares, non-positive sizes, markers not smaller than their squares, or more
// markers than the dictionary holds.
void check_board(const CharucoBoardSpec& board);

// The board as an 8-bit grey image to print: each square `square_px` pixels, with a
// white margin of `margin_px` around it.
cv::Mat draw_charuco_board(const CharucoBoardSpec& board, int square_px, int margin_px);

// The board's inner chessboard corners found in one picture.
struct BoardView {
  std::string name;                   // where the picture came from (file name, frame)
  std::vector<cv::Point2f> corners_px;  // OpenCV pixel convention
  std::vector<int> corner_ids;          // which inner corner each is, 0 .. (squares_x-1)(squares_y-1)-1
};

// Finds the board's corners in an 8-bit grey or BGR image; nullopt when fewer than
// min_corners of them are found (a view with few corners says little about the lens).
std::optional<BoardView> detect_charuco_board(const CharucoBoardSpec& board, const cv::Mat& image,
                                              int min_corners = 8);

struct CalibrationOptions {
  bool distortion = true;  // false: a distortion-free pinhole (all coefficients held at 0)
  bool free_k3 = false;    // estimate the third radial coefficient (wide-angle lenses)
  int min_views = 4;
};

struct CameraCalibration {
  config::CameraConfig camera;  // width, height, fx fy cx cy, distortion k1 k2 p1 p2 k3
  double rms_reprojection_px = 0;
  std::vector<double> view_rms_px;  // per view, in the order given
  // One standard deviation of fx, fy, cx, cy (px) as OpenCV estimates it from the
  // residuals: large values mean the views do not pin the camera down (too few, or all
  // frontal: vary the board's tilt).
  double fx_sigma_px = 0, fy_sigma_px = 0, cx_sigma_px = 0, cy_sigma_px = 0;
  int views = 0;
};

// Calibrates from the views (of one camera, all of image_size). Throws
// std::invalid_argument naming the count when there are fewer than options.min_views,
// and std::runtime_error when OpenCV's solve fails or gives a non-finite camera.
CameraCalibration calibrate_from_views(const CharucoBoardSpec& board, const std::vector<BoardView>& views,
                                       cv::Size image_size, const CalibrationOptions& options = {});

// Writes an OpenCV calibration file that config::load_camera reads (camera_id,
// image_width, image_height, camera_matrix, distortion_coefficients, with the RMS error
// and view count); the board and the uncertainties go in comments. Throws
// std::runtime_error naming the path when it cannot be written.
void write_camera_file(const std::string& path, const CameraCalibration& calibration, const std::string& camera_id,
                       const CharucoBoardSpec& board);

}  // namespace arphys::tracking
