// arphys-calibrate-camera: the camera file the tracker needs, from pictures of a printed
// ChArUco board (an image folder, a video file or a live V4L2 camera). Also draws the
// board to print. See tracker/calibration/charuco_calibration.hpp.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "configs/loader/camera_config.hpp"
#include "tracker/calibration/charuco_calibration.hpp"
#include "tracker/sources/frame_source.hpp"

namespace {

using namespace arphys;
using namespace arphys::tracking;

// Ctrl-C ends the collection (a live camera runs until --max-views): the views so far are used.
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

CharucoBoardSpec parse_board(const std::string& squares, double square_size_m, double marker_size_m,
                             const std::string& dictionary) {
  std::smatch m;
  if (!std::regex_match(squares, m, std::regex(R"((\d+)x(\d+))")))
    throw std::invalid_argument("--board '" + squares + "': expected COLUMNSxROWS of squares, e.g. 7x5");
  CharucoBoardSpec board;
  board.squares_x = std::stoi(m[1]);
  board.squares_y = std::stoi(m[2]);
  board.square_size_m = square_size_m;
  board.marker_size_m = marker_size_m;
  board.dictionary = dictionary;
  check_board(board);
  return board;
}

// Mean distance between the corners two views share, pixels (infinite if none shared).
double corner_motion_px(const BoardView& a, const BoardView& b) {
  double sum = 0;
  int shared = 0;
  for (std::size_t i = 0; i < a.corner_ids.size(); ++i)
    for (std::size_t j = 0; j < b.corner_ids.size(); ++j)
      if (a.corner_ids[i] == b.corner_ids[j]) {
        sum += cv::norm(a.corners_px[i] - b.corners_px[j]);
        ++shared;
      }
  return shared == 0 ? 1e9 : sum / shared;
}

// The command line.
struct Options {
  std::string source, out, camera_id = "camera", board_image, squares = "7x5", dictionary = "DICT_5X5_100";
  double square_size_m = 0.03, marker_size_m = 0.022, fps = 30, min_motion_px = 20;
  int dpi = 300, every = 0, max_views = 40, min_corners = 8, width = 0, height = 0;
  bool no_distortion = false, free_k3 = false;
};

void add_options(CLI::App& app, Options& o) {
  app.add_option("--source", o.source, "image folder (name order), video file, or /dev/videoN");
  app.add_option("--out", o.out, "camera file to write (OpenCV YAML)");
  app.add_option("--camera-id", o.camera_id, "camera_id written into the file")->capture_default_str();
  app.add_option("--write-board", o.board_image, "draw the board to this image file (PNG) and exit");
  app.add_option("--dpi", o.dpi, "--write-board: printer resolution, dots per inch")
      ->check(CLI::Range(50, 2400))
      ->capture_default_str();
  app.add_option("--board", o.squares, "squares of the board, COLUMNSxROWS")->capture_default_str();
  app.add_option("--square-size", o.square_size_m, "side of a printed square, metres (measure the print)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--marker-size", o.marker_size_m, "side of a printed marker, metres")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--dictionary", o.dictionary, "ArUco dictionary of the board's markers")->capture_default_str();
  app.add_option("--every", o.every, "use every Nth frame (default: 1 for a folder, 5 for a video or camera)")
      ->check(CLI::PositiveNumber);
  app.add_option("--min-motion", o.min_motion_px,
                 "video/camera: a view whose corners moved less than this from the last view kept adds nothing and "
                 "is skipped, pixels")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--max-views", o.max_views, "stop after this many views (or at Ctrl-C: the views so far are used)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--min-corners", o.min_corners, "a picture is a view when this many board corners are found")
      ->check(CLI::Range(4, 10000))
      ->capture_default_str();
  app.add_option("--fps", o.fps, "image folder: nominal frame rate (for the frame stamps only)")
      ->check(CLI::PositiveNumber);
  app.add_option("--width", o.width, "V4L2: requested frame width, pixels");
  app.add_option("--height", o.height, "V4L2: requested frame height, pixels");
  app.add_flag("--no-distortion", o.no_distortion, "fit a distortion-free pinhole (all coefficients 0)");
  app.add_flag("--free-k3", o.free_k3,
               "also fit the third radial coefficient k3 (wide-angle lenses); held at 0 by default");
}

// --write-board: the board drawn at the printer's resolution.
void write_board(const Options& o, const CharucoBoardSpec& board) {
  const int square_px = static_cast<int>(std::lround(o.square_size_m / 0.0254 * o.dpi));
  const cv::Mat image = draw_charuco_board(board, square_px, square_px / 2);
  if (!cv::imwrite(o.board_image, image))
    throw std::runtime_error("cannot write the board image '" + o.board_image + "'");
  std::printf(
      "wrote %s: %dx%d px (%.1f x %.1f cm at %d dpi), %s squares of %.4f m, %s. Print it at 100 %% scale "
      "on a flat backing, measure a square, and pass that size as --square-size.\n",
      o.board_image.c_str(), image.cols, image.rows, 2.54 * image.cols / o.dpi, 2.54 * image.rows / o.dpi, o.dpi,
      o.squares.c_str(), o.square_size_m, o.dictionary.c_str());
}

// The views of the board in the source's pictures (every --every-th; from a video, only those
// that moved), until --max-views, the source's end or Ctrl-C; image_size: the pictures'.
std::vector<BoardView> collect_views(const Options& o, const CharucoBoardSpec& board, cv::Size& image_size) {
  const auto frames = open_frame_source(o.source, o.fps, o.width, o.height);
  const bool stills = frames->frames_independent();
  const int stride = o.every > 0 ? o.every : (stills ? 1 : 5);
  std::vector<BoardView> views;
  int64_t read = 0, with_board = 0;
  int idle_polls = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  while (static_cast<int>(views.size()) < o.max_views && !g_stop) {
    const auto frame = frames->next(1000);
    if (!frame) {
      if (frames->finished()) break;
      if (++idle_polls >= 10) throw std::runtime_error("no frame from " + frames->describe() + " for 10 s");
      continue;
    }
    idle_polls = 0;
    if (read++ % stride != 0) continue;
    const std::string name = frame->name.empty() ? "frame " + std::to_string(frame->seq) : frame->name;
    if (image_size.empty()) image_size = frame->image.size();
    if (frame->image.size() != image_size)
      throw std::runtime_error(name + " is " + std::to_string(frame->image.cols) + "x" +
                               std::to_string(frame->image.rows) + ", the first picture " +
                               std::to_string(image_size.width) + "x" + std::to_string(image_size.height) +
                               ": one camera, one resolution");
    auto view = detect_charuco_board(board, frame->image, o.min_corners);
    if (!view) continue;
    ++with_board;
    if (!stills && !views.empty() && corner_motion_px(views.back(), *view) < o.min_motion_px) continue;
    view->name = name;
    views.push_back(*view);
    std::fprintf(stderr, "[calibrate] %s: %zu corners, view %zu of at most %d\n", name.c_str(), view->corners_px.size(),
                 views.size(), o.max_views);
  }
  std::fprintf(stderr, "[calibrate] %s%lld pictures read, the board found in %lld, %zu views kept\n",
               g_stop ? "stopped: " : "", static_cast<long long>(read), static_cast<long long>(with_board),
               views.size());
  return views;
}

// The fit as the tracker will read it, and the views that fit worst (a blurred or
// mis-detected picture shows here).
void report(const std::string& out, const CameraCalibration& fit, const std::vector<BoardView>& views) {
  const config::CameraConfig written = config::load_camera(out);
  std::printf("%s: %dx%d, fx %.2f +- %.2f, fy %.2f +- %.2f, cx %.2f +- %.2f, cy %.2f +- %.2f px; distortion",
              out.c_str(), written.width_px, written.height_px, written.fx_px, fit.fx_sigma_px, written.fy_px,
              fit.fy_sigma_px, written.cx_px, fit.cx_sigma_px, written.cy_px, fit.cy_sigma_px);
  for (const double d : written.distortion) std::printf(" %.5f", d);
  std::printf("\nRMS reprojection error %.3f px over %d views", fit.rms_reprojection_px, fit.views);
  std::vector<std::size_t> order(views.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return fit.view_rms_px[a] > fit.view_rms_px[b]; });
  std::printf("; worst:");
  for (std::size_t k = 0; k < std::min<std::size_t>(3, order.size()); ++k)
    std::printf(" %s %.3f px", views[order[k]].name.c_str(), fit.view_rms_px[order[k]]);
  std::printf("\n");
  if (fit.rms_reprojection_px > 1.0)
    std::printf(
        "warning: an RMS error above 1 px usually means a wrong --square-size/--marker-size, a bent board or "
        "blurred pictures\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "arphys-calibrate-camera: calibrates a camera from pictures of a printed ChArUco board and writes the\n"
      "OpenCV calibration file the tracker reads (--camera). Print the board first (--write-board), measure a\n"
      "printed square, and take 15-40 pictures: the board across the whole image, near and far, tilted\n"
      "20-45 degrees in different directions, sharp (no motion blur)."};
  Options o;
  add_options(app, o);
  CLI11_PARSE(app, argc, argv);
  try {
    const CharucoBoardSpec board = parse_board(o.squares, o.square_size_m, o.marker_size_m, o.dictionary);
    if (!o.board_image.empty()) {
      write_board(o, board);
      return 0;
    }
    if (o.source.empty() || o.out.empty()) {
      std::fprintf(stderr, "arphys-calibrate-camera: give --source and --out (or --write-board); see --help\n");
      return 2;
    }
    cv::Size image_size;
    const std::vector<BoardView> views = collect_views(o, board, image_size);
    CalibrationOptions options;
    options.distortion = !o.no_distortion;
    options.free_k3 = o.free_k3;
    const CameraCalibration fit = calibrate_from_views(board, views, image_size, options);
    write_camera_file(o.out, fit, o.camera_id, board);
    report(o.out, fit, views);
    return 0;
  } catch (const std::exception& e) {  // (config::ConfigError names the file and key itself)
    std::fprintf(stderr, "arphys-calibrate-camera: %s\n", e.what());
  }
  return 1;
}
