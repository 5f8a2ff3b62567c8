#include "tracker/calibration/charuco_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <sstream>
#include <stdexcept>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "tracker/detection/marker_family.hpp"

namespace arphys::tracking {

namespace {

std::string number(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

struct OpenCvBoard {
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  cv::Ptr<cv::aruco::CharucoBoard> board;
};

OpenCvBoard make_board(const CharucoBoardSpec& spec) {
  check_board(spec);
  OpenCvBoard b;
  b.dictionary = cv::aruco::getPredefinedDictionary(aruco_dictionary_id(spec.dictionary));
  b.board = cv::aruco::CharucoBoard::create(spec.squares_x, spec.squares_y, static_cast<float>(spec.square_size_m),
                                            static_cast<float>(spec.marker_size_m), b.dictionary);
  return b;
}

}  // namespace

void check_board(const CharucoBoardSpec& board) {
  if (board.squares_x < 2 || board.squares_y < 2 || board.squares_x > 64 || board.squares_y > 64)
    throw std::invalid_argument("ChArUco board: " + std::to_string(board.squares_x) + "x" +
                                std::to_string(board.squares_y) + " squares, expected 2 to 64 along each side");
  if (!(board.square_size_m > 0) || !std::isfinite(board.square_size_m))
    throw std::invalid_argument("ChArUco board: square_size_m = " + number(board.square_size_m) +
                                ", expected a positive length in metres");
  if (!(board.marker_size_m > 0) || !(board.marker_size_m < board.square_size_m))
    throw std::invalid_argument("ChArUco board: marker_size_m = " + number(board.marker_size_m) +
                                ", expected a positive length below the square's " + number(board.square_size_m) + " m");
  const int id = aruco_dictionary_id(board.dictionary);  // (throws naming an unknown dictionary)
  const int available = cv::aruco::getPredefinedDictionary(id)->bytesList.rows;
  const int needed = board.squares_x * board.squares_y / 2;
  if (needed > available)
    throw std::invalid_argument("ChArUco board: " + std::to_string(board.squares_x) + "x" +
                                std::to_string(board.squares_y) + " squares carry " + std::to_string(needed) +
                                " markers, but " + board.dictionary + " has only " + std::to_string(available));
}

cv::Mat draw_charuco_board(const CharucoBoardSpec& spec, int square_px, int margin_px) {
  if (square_px < 8 || margin_px < 0)
    throw std::invalid_argument("draw_charuco_board: square_px = " + std::to_string(square_px) + ", margin_px = " +
                                std::to_string(margin_px) + ", expected at least 8 and non-negative");
  const OpenCvBoard b = make_board(spec);
  cv::Mat image;
  b.board->draw(cv::Size(spec.squares_x * square_px + 2 * margin_px, spec.squares_y * square_px + 2 * margin_px), image,
                margin_px, 1);
  return image;
}

std::optional<BoardView> detect_charuco_board(const CharucoBoardSpec& spec, const cv::Mat& image, int min_corners) {
  const OpenCvBoard b = make_board(spec);
  if (image.empty()) return std::nullopt;
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  std::vector<int> marker_ids;
  std::vector<std::vector<cv::Point2f>> marker_corners, rejected;
  const cv::Ptr<cv::aruco::DetectorParameters> parameters = cv::aruco::DetectorParameters::create();
  cv::aruco::detectMarkers(grey, b.dictionary, marker_corners, marker_ids, parameters, rejected);
  if (marker_ids.empty()) return std::nullopt;
  // Markers the first pass missed, looked for where the board says they must be.
  cv::aruco::refineDetectedMarkers(grey, b.board, marker_corners, marker_ids, rejected);
  BoardView view;
  cv::Mat corners, ids;
  // Without a camera model the corners are interpolated by local homographies, then
  // refined on the image.
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, grey, b.board, corners, ids);
  if (ids.total() < static_cast<std::size_t>(std::max(4, min_corners))) return std::nullopt;
  view.corners_px.assign(corners.begin<cv::Point2f>(), corners.end<cv::Point2f>());
  view.corner_ids.assign(ids.begin<int>(), ids.end<int>());
  // OpenCV 4.5.4 to 4.12 shift the refined corners by +0.5 px (opencv#25539, fixed by
  // opencv#28380 in 2026): a calibration from them puts the principal point half a pixel
  // to one side, and every pose the tracker then solves is off by that. Refined again here
  // (cornerSubPix converges to the saddle point from either start), in OpenCV's pixel
  // convention whatever the installed version does. The window stays clear of the
  // markers' edges (their sides would pull the saddle point): half the distance to the
  // nearest marker corner, 2 to 10 px.
  for (std::size_t k = 0; k < view.corners_px.size(); ++k) {
    double nearest_px = 1e9;
    for (const auto& marker : marker_corners)
      for (const cv::Point2f& c : marker) nearest_px = std::min(nearest_px, static_cast<double>(cv::norm(c - view.corners_px[k])));
    const int half = std::clamp(static_cast<int>(0.5 * nearest_px), 2, 10);
    std::vector<cv::Point2f> one{view.corners_px[k]};
    cv::cornerSubPix(grey, one, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 100, 1e-4));
    view.corners_px[k] = one[0];
  }
  return view;
}

CameraCalibration calibrate_from_views(const CharucoBoardSpec& spec, const std::vector<BoardView>& views,
                                       cv::Size image_size, const CalibrationOptions& options) {
  const OpenCvBoard b = make_board(spec);
  if (static_cast<int>(views.size()) < options.min_views)
    throw std::invalid_argument("calibration: " + std::to_string(views.size()) + " views of the board, expected at least " +
                                std::to_string(options.min_views) + " (from different angles and distances)");
  if (image_size.width <= 0 || image_size.height <= 0)
    throw std::invalid_argument("calibration: image size " + std::to_string(image_size.width) + "x" +
                                std::to_string(image_size.height) + ", expected positive");
  std::vector<cv::Mat> corners, ids;
  for (const BoardView& view : views) {
    corners.push_back(cv::Mat(view.corners_px, true));
    ids.push_back(cv::Mat(view.corner_ids, true));
  }
  int flags = 0;
  if (!options.distortion) {
    flags |= cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
  } else if (!options.free_k3) {
    flags |= cv::CALIB_FIX_K3;
  }
  cv::Mat K, D, sigma_intrinsics, sigma_extrinsics, view_errors;
  std::vector<cv::Mat> rvecs, tvecs;
  double rms = 0;
  try {
    rms = cv::aruco::calibrateCameraCharuco(corners, ids, b.board, image_size, K, D, rvecs, tvecs, sigma_intrinsics,
                                            sigma_extrinsics, view_errors, flags);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("calibration: OpenCV could not solve for the camera (" + std::string(e.what()) +
                             "): are the views varied in angle and distance?");
  }
  if (!std::isfinite(rms) || K.empty() || !cv::checkRange(K) || !cv::checkRange(D) || !(K.at<double>(0, 0) > 0) ||
      !(K.at<double>(1, 1) > 0))
    throw std::runtime_error("calibration: the solve gave no finite camera (rms " + number(rms) + " px)");
  CameraCalibration out;
  out.views = static_cast<int>(views.size());
  out.rms_reprojection_px = rms;
  out.camera.width_px = image_size.width;
  out.camera.height_px = image_size.height;
  out.camera.fx_px = K.at<double>(0, 0);
  out.camera.fy_px = K.at<double>(1, 1);
  out.camera.cx_px = K.at<double>(0, 2);
  out.camera.cy_px = K.at<double>(1, 2);
  const cv::Mat D64 = D.reshape(1, 1);
  for (int k = 0; k < 5; ++k) out.camera.distortion.push_back(k < static_cast<int>(D64.total()) ? D64.at<double>(k) : 0.0);
  out.view_rms_px.assign(view_errors.begin<double>(), view_errors.end<double>());
  const auto sigma = [&](int k) { return k < static_cast<int>(sigma_intrinsics.total()) ? sigma_intrinsics.at<double>(k) : 0.0; };
  out.fx_sigma_px = sigma(0);
  out.fy_sigma_px = sigma(1);
  out.cx_sigma_px = sigma(2);
  out.cy_sigma_px = sigma(3);
  return out;
}

void write_camera_file(const std::string& path, const CameraCalibration& calibration, const std::string& camera_id,
                       const CharucoBoardSpec& board) {
  cv::FileStorage file;
  try {
    file.open(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception&) {
  }
  if (!file.isOpened()) throw std::runtime_error("cannot write the camera file '" + path + "'");
  const config::CameraConfig& c = calibration.camera;
  std::ostringstream board_text, sigma_text;
  board_text << "ChArUco board " << board.squares_x << "x" << board.squares_y << " squares of " << board.square_size_m
             << " m, markers " << board.marker_size_m << " m, " << board.dictionary;
  sigma_text << "one standard deviation: fx " << calibration.fx_sigma_px << ", fy " << calibration.fy_sigma_px << ", cx "
             << calibration.cx_sigma_px << ", cy " << calibration.cy_sigma_px << " px";
  file.writeComment("Written by arphys-calibrate-camera from " + std::to_string(calibration.views) + " views of a " +
                    board_text.str());
  file.writeComment(sigma_text.str());
  const std::time_t now = std::time(nullptr);
  char stamp[64];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  file << "calibration_time" << std::string(stamp);
  file << "camera_id" << camera_id;
  file << "image_width" << c.width_px;
  file << "image_height" << c.height_px;
  file << "camera_matrix" << cv::Mat(cv::Matx33d(c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1));
  file << "distortion_coefficients" << cv::Mat(c.distortion, true).reshape(1, 1);
  file << "avg_reprojection_error" << calibration.rms_reprojection_px;
  file << "nr_of_frames" << calibration.views;
  file.release();
}

}  // namespace arphys::tracking
