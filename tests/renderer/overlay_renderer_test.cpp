// The overlay against analytic projection: a box drawn at a known pose covers the
// pixels whose centres fall inside its projected outline (silhouette IoU >= 0.98,
// centroid within 0.5 px); a phantom in front hides it pixel for pixel; pixels no
// virtual object covers keep the frame's values exactly.
#include <gtest/gtest.h>

#include <cstdio>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "renderer/drawing/overlay_renderer.hpp"

namespace arphys::rendering {
namespace {

config::CameraConfig camera_640x480() {
  config::CameraConfig c;
  c.width_px = 640;
  c.height_px = 480;
  c.fx_px = 554.26;
  c.fy_px = 560.0;  // unequal on purpose: catches swapped axes
  c.cx_px = 319.5;
  c.cy_px = 239.5;
  return c;
}

Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Vector3d& axis, double angle) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  X.translation() = p;
  return X;
}

// Pixels whose centre lies inside the convex outline of the box's projected corners.
cv::Mat analytic_silhouette(const config::CameraConfig& c, const Eigen::Vector3d& size, const Eigen::Isometry3d& X_CO) {
  std::vector<cv::Point2f> projected;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(), (i & 4 ? 0.5 : -0.5) * size.z());
    const Eigen::Vector3d p = X_CO * corner;
    projected.emplace_back(c.fx_px * p.x() / p.z() + c.cx_px, c.fy_px * p.y() / p.z() + c.cy_px);
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(projected, hull);
  cv::Mat mask(c.height_px, c.width_px, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      if (cv::pointPolygonTest(hull, cv::Point2f(x, y), false) > 0) mask.at<uint8_t>(y, x) = 255;
    }
  }
  return mask;
}

cv::Point2d centroid(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

TEST(OverlayRenderer, RegistersWithTheAnalyticProjection) {
  const auto camera = camera_640x480();
  OverlayRenderer renderer(CameraProjection::from_config(camera));
  const Eigen::Vector3d size(0.15, 0.1, 0.08);
  const GpuMesh* box = renderer.upload(geometry::make_box_mesh(size));
  for (const auto& X_CO : {pose({0.03, -0.02, 0.6}, {1, 2, 0.5}, 0.7), pose({-0.2, 0.1, 1.1}, {0.3, -1, 0.2}, 2.0),
                           pose({0.15, 0.12, 0.45}, {0, 0, 1}, 0.3)}) {
    OverlayLayers layers;
    layers.items.push_back({box, X_CO, {0.2f, 0.6f, 0.9f, 1.0f}, DrawStyle::kShaded});
    const cv::Mat rgba = renderer.render_rgba(layers);
    cv::Mat drawn;
    cv::extractChannel(rgba, drawn, 3);
    cv::threshold(drawn, drawn, 0, 255, cv::THRESH_BINARY);
    const cv::Mat truth = analytic_silhouette(camera, size, X_CO);
    const double intersection = cv::countNonZero(drawn & truth);
    const double unite = cv::countNonZero(drawn | truth);
    // The issue asks IoU >= 0.98 and 0.5 px; GL's pixel-centre rule matches the analytic
    // one exactly, so assert tighter: a half-pixel convention slip moves the centroid 0.5 px.
    EXPECT_GE(intersection / unite, 0.995);
    const cv::Point2d a = centroid(drawn), b = centroid(truth);
    EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 0.1) << "centroid (" << a.x << ", " << a.y << ") vs (" << b.x << ", "
                                                     << b.y << ")";
  }
}

// A webcam's barrel lens (k1 -0.28): the overlay is drawn through it, so a box near the
// image's corners covers the pixels the lens shows it on (each pixel centre, undistorted,
// falls inside the pinhole outline), not those a pinhole would, 10-20 px away.
TEST(OverlayRenderer, DrawsThroughTheCamerasLens) {
  auto camera = camera_640x480();
  camera.distortion = {-0.28, 0.09, 0.0005, -0.0003, 0.0};
  OverlayRenderer renderer(CameraProjection::from_config(camera));
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  std::vector<cv::Point2d> pixels, pinhole;
  for (int y = 0; y < camera.height_px; ++y)
    for (int x = 0; x < camera.width_px; ++x) pixels.emplace_back(x, y);
  cv::undistortPoints(pixels, pinhole, K, camera.distortion, cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  const Eigen::Vector3d size(0.06, 0.05, 0.04);
  const GpuMesh* box = renderer.upload(geometry::make_box_mesh(size));
  int k = 0;
  for (const auto& at : {Eigen::Vector2d(70, 60), Eigen::Vector2d(575, 55), Eigen::Vector2d(60, 420),
                         Eigen::Vector2d(580, 425), Eigen::Vector2d(320, 240)}) {
    // The box's centre on the ray through that pinhole pixel, 0.6 m away.
    const double z = 0.6;
    const Eigen::Isometry3d X_CO =
        pose({(at.x() - camera.cx_px) / camera.fx_px * z, (at.y() - camera.cy_px) / camera.fy_px * z, z}, {1, 1, 0.3}, 0.5 * k++);
    OverlayLayers layers;
    layers.items.push_back({box, X_CO, {0.2f, 0.6f, 0.9f, 1.0f}, DrawStyle::kShaded});
    cv::Mat drawn;
    cv::extractChannel(renderer.render_rgba(layers), drawn, 3);
    cv::threshold(drawn, drawn, 127, 255, cv::THRESH_BINARY);  // (the warp interpolates coverage)
    const cv::Mat outline = analytic_silhouette(camera, size, X_CO);  // the pinhole outline
    cv::Mat truth(camera.height_px, camera.width_px, CV_8UC1, cv::Scalar(0));
    for (int y = 0; y < truth.rows; ++y)
      for (int x = 0; x < truth.cols; ++x) {
        const cv::Point2d& q = pinhole[static_cast<std::size_t>(y) * truth.cols + x];
        const int qx = static_cast<int>(std::lround(q.x)), qy = static_cast<int>(std::lround(q.y));
        if (qx >= 0 && qy >= 0 && qx < truth.cols && qy < truth.rows && outline.at<uint8_t>(qy, qx)) truth.at<uint8_t>(y, x) = 255;
      }
    ASSERT_GT(cv::countNonZero(truth), 500);
    const double iou = cv::countNonZero(drawn & truth) / static_cast<double>(cv::countNonZero(drawn | truth));
    const cv::Point2d a = centroid(drawn), b = centroid(truth), c = centroid(outline);
    std::printf("box at pinhole (%.0f, %.0f): IoU %.3f, centroid off %.2f px; the pinhole outline is %.1f px away\n", at.x(),
                at.y(), iou, std::hypot(a.x - b.x, a.y - b.y), std::hypot(c.x - b.x, c.y - b.y));
    EXPECT_GE(iou, 0.97);
    EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 0.3);
    if (at.x() != 320) {
      EXPECT_GT(std::hypot(c.x - b.x, c.y - b.y), 8.0);  // what a pinhole overlay would be off by
    }
  }
}

TEST(OverlayRenderer, PhantomOccludesAndUncoveredPixelsKeepTheFrame) {
  const auto camera = camera_640x480();
  OverlayRenderer renderer(CameraProjection::from_config(camera));
  const Eigen::Vector3d virtual_size(0.2, 0.2, 0.2), real_size(0.1, 0.3, 0.05);
  const GpuMesh* virtual_box = renderer.upload(geometry::make_box_mesh(virtual_size));
  const GpuMesh* real_box = renderer.upload(geometry::make_box_mesh(real_size));
  const Eigen::Isometry3d X_CV = pose({0, 0, 1.0}, {1, 1, 0}, 0.4);
  const Eigen::Isometry3d X_CR = pose({0.03, 0, 0.7}, {0, 0, 1}, 0.2);  // in front of the virtual box
  cv::Mat frame(480, 640, CV_8UC3);
  cv::randu(frame, cv::Scalar::all(0), cv::Scalar::all(256));

  OverlayLayers layers;
  layers.items.push_back({virtual_box, X_CV, {0.9f, 0.5f, 0.2f, 1.0f}, DrawStyle::kShaded});
  layers.items.push_back({real_box, X_CR, {1, 1, 1, 1}, DrawStyle::kPhantom});
  const cv::Mat out = renderer.composite(layers, frame);
  const cv::Mat virtual_mask = analytic_silhouette(camera, virtual_size, X_CV);
  const cv::Mat real_mask = analytic_silhouette(camera, real_size, X_CR);
  // Interior pixels (one pixel away from either outline) checked one by one.
  cv::Mat virtual_in, real_in, real_out, virtual_out;
  cv::erode(virtual_mask, virtual_in, cv::Mat());
  cv::erode(real_mask, real_in, cv::Mat());
  cv::dilate(real_mask, real_out, cv::Mat());
  cv::dilate(virtual_mask, virtual_out, cv::Mat());
  int hidden_wrong = 0, shown_wrong = 0, outside_changed = 0, hidden = 0, shown = 0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      const bool same = out.at<cv::Vec3b>(y, x) == frame.at<cv::Vec3b>(y, x);
      if (real_in.at<uint8_t>(y, x)) {  // behind the phantom: the camera's pixels
        ++hidden;
        hidden_wrong += same ? 0 : 1;
      } else if (virtual_in.at<uint8_t>(y, x) && !real_out.at<uint8_t>(y, x)) {
        ++shown;
        shown_wrong += same ? 1 : 0;
      } else if (!virtual_out.at<uint8_t>(y, x)) {
        outside_changed += same ? 0 : 1;
      }
    }
  }
  EXPECT_GT(hidden, 1000);
  EXPECT_GT(shown, 1000);
  EXPECT_EQ(hidden_wrong, 0);
  EXPECT_EQ(shown_wrong, 0);
  EXPECT_EQ(outside_changed, 0);
}

TEST(OverlayRenderer, RefusesAFrameOfAnotherSize) {
  OverlayRenderer renderer(CameraProjection::from_config(camera_640x480()));
  EXPECT_THROW(renderer.composite({}, cv::Mat(240, 320, CV_8UC3)), std::invalid_argument);
  EXPECT_THROW(CameraProjection::from_config(camera_640x480(), 1.0, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::rendering
