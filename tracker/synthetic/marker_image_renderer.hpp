#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "simulator/geometry/pose.hpp"
#include "tracker/pose/camera_model.hpp"

namespace arphys::tracking {

// Images of markers at known poses, for tests and the tracker benchmark: exact ground
// truth without a person or a printer. A marker's texture (its cells, from libapriltag
// or OpenCV) is mapped by the exact plane-to-image homography into a supersampled canvas
// and box-filtered down, which integrates each pixel's area as a sensor does. A camera
// with distortion coefficients sees the pinhole canvas through its lens (OpenCV's model,
// the same the pose solvers undo); what a barrel lens sees beyond the pinhole image's
// edge is filled from that edge, so keep markers off the outermost border.

struct MarkerPlacement {
  std::string family = "tag36h11";
  int id = 0;
  double size_m = 0.05;  // side of the black square
  geometry::Pose X_CM = geometry::Pose::Identity();
};

struct ImageEffects {
  double noise_sigma = 0;      // additive Gaussian noise, grey levels
  double blur_length_px = 0;   // linear motion blur length
  double blur_angle_rad = 0;   // its direction
  uint32_t seed = 1;
  int black = 30, white = 225;  // printed ink and paper under the scene's light
};

// Seeded procedural clutter (rectangles, discs, lines, shading): a background with
// edges and corners, so detectors have something to reject.
cv::Mat clutter_background(int width_px, int height_px, uint32_t seed);

// Renders the markers over `background` (8-bit grey of the camera's size; empty: plain
// mid-grey). Markers are drawn in order (later ones cover earlier ones); a marker seen
// from behind is not drawn (back-face culling; the object's own body is not drawn).
cv::Mat render_markers(const CameraModel& camera, const std::vector<MarkerPlacement>& markers,
                       const cv::Mat& background, const ImageEffects& effects = {}, int supersample = 4);

// Renders an 8-bit grey picture (a printed calibration board, say) lying in the plane
// z = 0 of frame M, centred on M's origin, x to its right and y up, `width_m` wide
// (its height by its aspect), the same way as the markers: through the lens, area-integrated.
cv::Mat render_planar_image(const CameraModel& camera, const cv::Mat& picture, double width_m,
                            const geometry::Pose& X_CM, const cv::Mat& background = {},
                            const ImageEffects& effects = {}, int supersample = 4);

// The true corners of a placed marker in DetectedMarker's order and pixel convention.
std::array<Eigen::Vector2d, 4> true_corners_px(const CameraModel& camera, const MarkerPlacement& marker);

// A camera-from-marker pose looking at the marker from `distance_m` along the ray
// through pixel (u, v), the marker's normal tilted by `view_angle_rad` from that ray
// about an axis at `tilt_axis_rad` in the image plane, rotated in plane by `roll_rad`.
geometry::Pose marker_pose_at(const CameraModel& camera, double u_px, double v_px, double distance_m,
                              double view_angle_rad, double tilt_axis_rad, double roll_rad);

}  // namespace arphys::tracking
