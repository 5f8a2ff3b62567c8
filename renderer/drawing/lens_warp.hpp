#pragma once
// The overlay through the camera's lens. GL draws a pinhole image; a calibrated camera
// with distortion coefficients shows the scene bent (a webcam's barrel lens moves points
// near the image's corners by 10-20 px), so an overlay drawn pinhole over its frames lands
// beside the real objects. The pinhole drawing is made on a canvas wide enough for all the
// lens sees and remapped, pixel by pixel, to where the lens puts it (OpenCV's model, the
// one the tracker's pose solvers undo).
#include <opencv2/core.hpp>

#include "renderer/drawing/camera_projection.hpp"

namespace arphys::rendering {

class LensWarp {
 public:
  // Inactive (nothing to do) when the camera has no distortion.
  explicit LensWarp(const CameraProjection& camera);

  bool active() const { return !map_x_.empty(); }
  // The pinhole projection to draw with: the camera's own when inactive, else a canvas
  // that also covers what the lens shows beyond the pinhole image's edges (at most three
  // times the image's size in each direction).
  const CameraProjection& canvas() const { return canvas_; }
  // A canvas-size premultiplied RGBA drawing, seen through the lens: camera-size RGBA.
  // (Premultiplied colour interpolates correctly; outside the canvas is transparent.)
  cv::Mat apply(const cv::Mat& canvas_rgba) const;

 private:
  CameraProjection canvas_;
  cv::Mat map_x_, map_y_;
};

}  // namespace arphys::rendering
