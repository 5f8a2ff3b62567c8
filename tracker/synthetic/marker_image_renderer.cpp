#include "tracker/synthetic/marker_image_renderer.hpp"

#include <cmath>
#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "tracker/detection/marker_family.hpp"
#include "tracker/pose/marker_pose.hpp"

namespace arphys::tracking {

cv::Mat clutter_background(int width_px, int height_px, uint32_t seed) {
  cv::RNG rng(seed);
  cv::Mat image(height_px, width_px, CV_8UC1);
  // Low-frequency shading.
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      image.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(128 + 30 * std::sin(x * 0.011 + seed) * std::cos(y * 0.013));
    }
  }
  for (int i = 0; i < 60; ++i) {
    const cv::Scalar level(rng.uniform(20, 235));
    // Each draw its own statement: the order of a call's arguments differs between
    // compilers, and the picture must not.
    const int ax = rng.uniform(0, width_px), ay = rng.uniform(0, height_px);
    const cv::Point a(ax, ay);
    switch (rng.uniform(0, 3)) {
      case 0: {
        const int w = rng.uniform(5, 80), h = rng.uniform(5, 80);
        cv::rectangle(image, a, a + cv::Point(w, h), level, cv::FILLED, cv::LINE_AA);
        break;
      }
      case 1: cv::circle(image, a, rng.uniform(3, 40), level, cv::FILLED, cv::LINE_AA); break;
      default: {
        const int bx = rng.uniform(0, width_px), by = rng.uniform(0, height_px), thickness = rng.uniform(1, 4);
        cv::line(image, a, cv::Point(bx, by), level, thickness, cv::LINE_AA);
      }
    }
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.7);
  return image;
}

std::array<Eigen::Vector2d, 4> true_corners_px(const CameraModel& camera, const MarkerPlacement& marker) {
  const auto corners = marker_corners_M(marker.size_m);
  std::array<Eigen::Vector2d, 4> uv;
  for (int k = 0; k < 4; ++k) uv[k] = camera.project(marker.X_CM * corners[k]);
  return uv;
}

namespace {

// The supersampled canvas a frame is drawn on, from its background.
cv::Mat start_canvas(const CameraModel& camera, const cv::Mat& background, int S) {
  cv::Mat base = background.empty() ? cv::Mat(camera.height_px, camera.width_px, CV_8UC1, cv::Scalar(128)) : background;
  CV_Assert(base.type() == CV_8UC1 && base.cols == camera.width_px && base.rows == camera.height_px);
  cv::Mat canvas;
  cv::resize(base, canvas, cv::Size(), S, S, cv::INTER_NEAREST);
  return canvas;
}

// Maps `texture` onto the canvas by the homography from texture pixels to the plane
// (plane_from_texture: texture pixel (u, v, 1) -> plane (x, y, 1), in metres) and from the
// plane (z = 0 of frame M) to the image.
void draw_texture(cv::Mat& canvas, int S, const CameraModel& camera, const cv::Mat& texture,
                  const cv::Matx33d& plane_from_texture, const geometry::Pose& X_CM) {
  // Canvas pixel centres sit at S * (p + 0.5) - 0.5 for image pixel coordinate p.
  const cv::Matx33d to_canvas(S, 0, 0.5 * S - 0.5, 0, S, 0.5 * S - 0.5, 0, 0, 1);
  const Eigen::Matrix3d R = X_CM.linear();
  const Eigen::Vector3d t = X_CM.translation();
  const cv::Matx33d Rt(R(0, 0), R(0, 1), t.x(), R(1, 0), R(1, 1), t.y(), R(2, 0), R(2, 1), t.z());
  const cv::Matx33d H = to_canvas * camera.K * Rt * plane_from_texture;
  // Warp only into the texture's bounding box: the canvas is 16x the frame's pixels.
  std::vector<cv::Point2d> texture_corners{{-0.5, -0.5}, {texture.cols - 0.5, -0.5},
                                           {texture.cols - 0.5, texture.rows - 0.5}, {-0.5, texture.rows - 0.5}};
  std::vector<cv::Point2d> canvas_corners;
  cv::perspectiveTransform(texture_corners, canvas_corners, cv::Mat(H));
  cv::Rect2d bounds = cv::boundingRect(std::vector<cv::Point2f>(canvas_corners.begin(), canvas_corners.end()));
  const cv::Rect roi = cv::Rect(static_cast<int>(std::floor(bounds.x)) - 2, static_cast<int>(std::floor(bounds.y)) - 2,
                                static_cast<int>(std::ceil(bounds.width)) + 5, static_cast<int>(std::ceil(bounds.height)) + 5) &
                       cv::Rect(0, 0, canvas.cols, canvas.rows);
  if (roi.area() <= 0) return;
  const cv::Matx33d shift(1, 0, -roi.x, 0, 1, -roi.y, 0, 0, 1);
  cv::Mat target = canvas(roi);
  cv::warpPerspective(texture, target, cv::Mat(shift * H), roi.size(), cv::INTER_LINEAR, cv::BORDER_TRANSPARENT);
}

// Whether a plane patch with these corners (frame M) is in front of the camera and faces
// it; and its nearest depth.
bool visible(const geometry::Pose& X_CM, const std::vector<Eigen::Vector3d>& corners_M, double* z_min) {
  bool in_front = true;
  *z_min = 1e9;
  for (const auto& c : corners_M) {
    const double z = (X_CM * c).z();
    in_front = in_front && z > 1e-3;
    *z_min = std::min(*z_min, z);
  }
  // Behind the camera, or seen from its back (a face of a box turned away): not drawn.
  const bool facing = X_CM.linear().col(2).dot(X_CM.translation()) < 0;
  return in_front && facing;
}

// For each canvas pixel of the lens's (distorted) image, where the pinhole canvas holds
// what it sees: the pixel's centre undistorted, in canvas coordinates. Found once per
// camera and canvas (undistorting a 2560x1920 canvas takes about a second).
struct LensMap {
  cv::Matx33d K;
  cv::Mat distortion;
  int S = 0;
  cv::Mat map_x, map_y;  // remap's fixed-point pair (CV_16SC2 and CV_16UC1)
};

const LensMap& lens_map(const CameraModel& camera, int S) {
  thread_local std::vector<LensMap> maps;
  for (const LensMap& m : maps)
    if (m.S == S && m.K == camera.K && m.distortion.size() == camera.distortion.size() &&
        cv::norm(m.distortion, camera.distortion, cv::NORM_INF) == 0 && m.map_x.cols == S * camera.width_px &&
        m.map_x.rows == S * camera.height_px)
      return m;
  LensMap m{camera.K, camera.distortion.clone(), S, {}, {}};
  const int w = S * camera.width_px, h = S * camera.height_px;
  std::vector<cv::Point2d> distorted;
  distorted.reserve(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) distorted.emplace_back((x + 0.5) / S - 0.5, (y + 0.5) / S - 0.5);
  std::vector<cv::Point2d> pinhole;
  cv::undistortPoints(distorted, pinhole, camera.K, camera.distortion, cv::noArray(), camera.K,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  cv::Mat map_x(h, w, CV_32F), map_y(h, w, CV_32F);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const cv::Point2d& q = pinhole[static_cast<std::size_t>(y) * w + x];
      map_x.at<float>(y, x) = static_cast<float>(S * (q.x + 0.5) - 0.5);
      map_y.at<float>(y, x) = static_cast<float>(S * (q.y + 0.5) - 0.5);
    }
  // In remap's own fixed-point form: from float maps it converts them on every call (a
  // tenth of a lens frame's cost; the frames are the same to the byte).
  cv::convertMaps(map_x, map_y, m.map_x, m.map_y, CV_16SC2);
  if (maps.size() >= 4) maps.erase(maps.begin());
  maps.push_back(std::move(m));
  return maps.back();
}

// The canvas through the lens (when the camera has distortion), box-filtered down to the
// frame (each pixel's area integrated, as a sensor does), then blurred and noised.
cv::Mat finish_frame(const cv::Mat& pinhole_canvas, const CameraModel& camera, int S, const ImageEffects& effects) {
  cv::Mat canvas = pinhole_canvas;
  if (!camera.distortion.empty() && cv::countNonZero(camera.distortion) > 0) {
    const LensMap& lens = lens_map(camera, S);
    // What the pinhole canvas does not cover (a barrel lens sees wider) is its nearest edge.
    cv::remap(pinhole_canvas, canvas, lens.map_x, lens.map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  }
  cv::Mat image;
  cv::resize(canvas, image, cv::Size(camera.width_px, camera.height_px), 0, 0, cv::INTER_AREA);
  if (effects.blur_length_px > 0.5) {
    const int size = static_cast<int>(std::ceil(effects.blur_length_px)) | 1;
    cv::Mat kernel = cv::Mat::zeros(size, size, CV_32F);
    const cv::Point2d centre((size - 1) / 2.0, (size - 1) / 2.0);
    const cv::Point2d half(std::cos(effects.blur_angle_rad) * effects.blur_length_px / 2,
                           std::sin(effects.blur_angle_rad) * effects.blur_length_px / 2);
    cv::line(kernel, centre - half, centre + half, cv::Scalar(1.0), 1, cv::LINE_AA);
    kernel /= cv::sum(kernel)[0];
    cv::filter2D(image, image, -1, kernel);
  }
  if (effects.noise_sigma > 0) {
    cv::Mat noise(image.size(), CV_32F);
    cv::RNG rng(effects.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, effects.noise_sigma);
    cv::Mat sum;
    image.convertTo(sum, CV_32F);
    sum += noise;
    sum.convertTo(image, CV_8U);  // rounds and saturates
  }
  return image;
}

}  // namespace

cv::Mat render_markers(const CameraModel& camera, const std::vector<MarkerPlacement>& markers,
                       const cv::Mat& background, const ImageEffects& effects, int supersample) {
  const int S = std::max(1, supersample);
  cv::Mat canvas = start_canvas(camera, background, S);
  for (const auto& m : markers) {
    int black_cells = 0;
    cv::Mat cells = marker_cells_image(m.family, m.id, &black_cells);
    const int N = cells.cols;
    const double cell_m = m.size_m / black_cells;
    double z_min = 0;
    const auto outline = marker_corners_M(m.size_m * N / black_cells);
    if (!visible(m.X_CM, std::vector<Eigen::Vector3d>(outline.begin(), outline.end()), &z_min)) continue;
    // Texture resolution near the canvas's, so bilinear sampling neither aliases nor blurs.
    const double cell_canvas_px = S * camera.K(0, 0) * cell_m / z_min;
    const int k = std::clamp(static_cast<int>(std::lround(cell_canvas_px)), 1, 64);
    cv::Mat texture;
    cv::resize(cells, texture, cv::Size(), k, k, cv::INTER_NEAREST);
    texture.convertTo(texture, CV_8U, (effects.white - effects.black) / 255.0, effects.black);
    // Texture pixel (u, v) -> marker plane (x, y, 1): pixel u spans [u - 0.5, u + 0.5] of
    // the continuous texture, x increases right and y up, the centre is the origin.
    const cv::Matx33d plane(cell_m / k, 0, (0.5 / k - N / 2.0) * cell_m, 0, -cell_m / k, (N / 2.0 - 0.5 / k) * cell_m, 0,
                            0, 1);
    draw_texture(canvas, S, camera, texture, plane, m.X_CM);
  }
  return finish_frame(canvas, camera, S, effects);
}

cv::Mat render_planar_image(const CameraModel& camera, const cv::Mat& picture, double width_m,
                            const geometry::Pose& X_CM, const cv::Mat& background, const ImageEffects& effects,
                            int supersample) {
  CV_Assert(picture.type() == CV_8UC1 && !picture.empty() && width_m > 0);
  const int S = std::max(1, supersample);
  cv::Mat canvas = start_canvas(camera, background, S);
  const double pixel_m = width_m / picture.cols;
  const double half_w = 0.5 * width_m, half_h = 0.5 * pixel_m * picture.rows;
  double z_min = 0;
  if (visible(X_CM, {{-half_w, -half_h, 0}, {half_w, -half_h, 0}, {half_w, half_h, 0}, {-half_w, half_h, 0}}, &z_min)) {
    // Picture pixel (u, v) -> plane: x right, y up, the picture's centre at the origin.
    const cv::Matx33d plane(pixel_m, 0, (0.5 - 0.5 * picture.cols) * pixel_m, 0, -pixel_m,
                            (0.5 * picture.rows - 0.5) * pixel_m, 0, 0, 1);
    cv::Mat texture;
    picture.convertTo(texture, CV_8U, (effects.white - effects.black) / 255.0, effects.black);
    draw_texture(canvas, S, camera, texture, plane, X_CM);
  }
  return finish_frame(canvas, camera, S, effects);
}

geometry::Pose marker_pose_at(const CameraModel& camera, double u_px, double v_px, double distance_m,
                              double view_angle_rad, double tilt_axis_rad, double roll_rad) {
  const Eigen::Vector3d ray =
      Eigen::Vector3d((u_px - camera.K(0, 2)) / camera.K(0, 0), (v_px - camera.K(1, 2)) / camera.K(1, 1), 1.0).normalized();
  // Frontal marker facing the camera along the ray: its z axis points back along it.
  const Eigen::Vector3d z = -ray;
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(z) * z;
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_facing;
  R_facing << x, y, z;
  // Tilt about an axis perpendicular to the ray, then roll about the marker normal.
  const Eigen::Vector3d tilt_axis = std::cos(tilt_axis_rad) * x + std::sin(tilt_axis_rad) * y;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(view_angle_rad, tilt_axis).toRotationMatrix() * R_facing *
                            Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  geometry::Pose X = geometry::Pose::Identity();
  X.linear() = R;
  X.translation() = ray * distance_m;
  return X;
}

}  // namespace arphys::tracking
