#include "renderer/drawing/lens_warp.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace arphys::rendering {

namespace {

bool any_distortion(const std::vector<double>& d) {
  return std::any_of(d.begin(), d.end(), [](double c) { return c != 0.0; });
}

// Pixels (OpenCV's convention) of the lens's image to where a pinhole camera of the same
// K would show them.
std::vector<cv::Point2d> undistorted(const std::vector<cv::Point2d>& distorted, const CameraProjection& camera) {
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> out;
  cv::undistortPoints(distorted, out, K, cv::Mat(camera.distortion, true).reshape(1, 1), cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  return out;
}

}  // namespace

LensWarp::LensWarp(const CameraProjection& camera) : canvas_(camera) {
  if (!any_distortion(camera.distortion)) return;
  const int W = camera.width_px, H = camera.height_px;
  // The canvas: the image, grown to where its border pixels come from (a barrel lens
  // sees wider than its pinhole), within three times the image's size.
  std::vector<cv::Point2d> border;
  for (int x = 0; x < W; ++x) {
    border.emplace_back(x, 0);
    border.emplace_back(x, H - 1);
  }
  for (int y = 0; y < H; ++y) {
    border.emplace_back(0, y);
    border.emplace_back(W - 1, y);
  }
  double x0 = 0, y0 = 0, x1 = W - 1, y1 = H - 1;
  for (const cv::Point2d& q : undistorted(border, camera)) {
    if (!std::isfinite(q.x) || !std::isfinite(q.y)) continue;
    x0 = std::min(x0, q.x);
    y0 = std::min(y0, q.y);
    x1 = std::max(x1, q.x);
    y1 = std::max(y1, q.y);
  }
  const int left = static_cast<int>(std::min(std::ceil(-x0) + 2, 1.0 * W));
  const int top = static_cast<int>(std::min(std::ceil(-y0) + 2, 1.0 * H));
  const int right = static_cast<int>(std::min(std::ceil(x1 - (W - 1)) + 2, 1.0 * W));
  const int bottom = static_cast<int>(std::min(std::ceil(y1 - (H - 1)) + 2, 1.0 * H));
  canvas_.width_px = W + left + right;
  canvas_.height_px = H + top + bottom;
  canvas_.cx_px = camera.cx_px + left;
  canvas_.cy_px = camera.cy_px + top;
  canvas_.distortion.clear();
  // Every image pixel's source on the canvas.
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<std::size_t>(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) pixels.emplace_back(x, y);
  const std::vector<cv::Point2d> sources = undistorted(pixels, camera);
  map_x_.create(H, W, CV_32F);
  map_y_.create(H, W, CV_32F);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const cv::Point2d& q = sources[static_cast<std::size_t>(y) * W + x];
      map_x_.at<float>(y, x) = static_cast<float>(q.x + left);
      map_y_.at<float>(y, x) = static_cast<float>(q.y + top);
    }
}

cv::Mat LensWarp::apply(const cv::Mat& canvas_rgba) const {
  if (!active()) return canvas_rgba;
  CV_Assert(canvas_rgba.cols == canvas_.width_px && canvas_rgba.rows == canvas_.height_px);
  cv::Mat out;
  cv::remap(canvas_rgba, out, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

}  // namespace arphys::rendering
