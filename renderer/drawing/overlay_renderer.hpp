#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "renderer/context/offscreen_context.hpp"
#include "renderer/drawing/camera_projection.hpp"
#include "renderer/drawing/gpu_mesh.hpp"
#include "renderer/drawing/lens_warp.hpp"

namespace arphys::rendering {

enum class DrawStyle {
  kShaded,       // a virtual object: lit, opaque
  kPhantom,      // a real object: depth only, so virtual objects behind it are hidden
  kTranslucent,  // a debug proxy (a real object's collision shape, as the paper's figure 7a)
};

struct DrawItem {
  const GpuMesh* mesh = nullptr;
  Eigen::Isometry3d X_CO = Eigen::Isometry3d::Identity();  // object in the OpenCV camera frame
  Eigen::Vector4f rgba{0.8f, 0.8f, 0.8f, 1.0f};             // translucent: alpha is the opacity
  DrawStyle style = DrawStyle::kShaded;
};

// A contact point and its normal, camera frame (drawn over everything: a debug layer).
struct ContactMark {
  Eigen::Vector3d p_C = Eigen::Vector3d::Zero();
  Eigen::Vector3d n_C = Eigen::Vector3d::UnitZ();
};

struct OverlayLayers {
  std::vector<DrawItem> items;
  std::vector<ContactMark> contacts;
  double contact_normal_length_m = 0.03;
  bool draw_world_axes = false;
  Eigen::Isometry3d X_CW = Eigen::Isometry3d::Identity();
  double axes_length_m = 0.1;
};

// Draws virtual objects from the camera's viewpoint, through its lens when it has
// distortion (LensWarp), and composites them over the camera frame. Phantoms first (depth only), then shaded objects, then translucent
// proxies, then the debug layers; the colour buffer holds premultiplied colour and
// coverage, so compositing keeps every pixel no virtual object covers exactly.
class OverlayRenderer {
 public:
  // A given context must have the size of the drawing canvas (the camera's, unless the
  // lens widens it: LensWarp::canvas()).
  explicit OverlayRenderer(const CameraProjection& projection, std::unique_ptr<OffscreenContext> context = nullptr);
  ~OverlayRenderer();

  // Uploads a mesh (context made current). The renderer owns it until destroyed.
  const GpuMesh* upload(const geometry::TriangleMesh& mesh);

  // Premultiplied RGBA (OpenCV row order, channels R G B A), valid until the next render.
  cv::Mat render_rgba(const OverlayLayers& layers);
  // The camera frame (8-bit BGR or grey, the camera's size) with the layers over it.
  // Throws std::invalid_argument when the frame's size or type does not fit.
  cv::Mat composite(const OverlayLayers& layers, const cv::Mat& frame);

  const CameraProjection& projection() const { return projection_; }
  std::string describe() const { return context_->describe(); }

 private:
  void draw_lines(const std::vector<Eigen::Vector3f>& points_C, const Eigen::Vector4f& rgba, bool as_points);

  CameraProjection projection_;
  LensWarp lens_;  // its canvas() is what GL draws on
  std::unique_ptr<OffscreenContext> context_;
  unsigned program_ = 0;
  int u_clip_from_object_ = -1, u_eye_from_object_ = -1, u_colour_ = -1, u_lit_ = -1;
  unsigned line_vao_ = 0, line_buffer_ = 0;
  std::vector<std::unique_ptr<GpuMesh>> meshes_;
};

// out = C + (1 - A) * frame for premultiplied RGBA (C, A) over an 8-bit BGR or grey frame;
// returns BGR. Pixels with A = 0 keep the frame's values exactly.
cv::Mat composite_over(const cv::Mat& premultiplied_rgba, const cv::Mat& frame);

}  // namespace arphys::rendering
