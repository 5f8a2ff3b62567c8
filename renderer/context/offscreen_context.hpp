#pragma once
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace arphys::rendering {

// The one seam between the renderer and the platform's GL: an offscreen OpenGL 3.3 core
// context with an RGBA colour buffer and a 24-bit depth buffer. OSMesa implements it
// today (Debian 12's Mesa 22, llvmpipe); Mesa 25.1 removed OSMesa upstream, and an EGL
// surfaceless context can implement the same two calls.
class OffscreenContext {
 public:
  virtual ~OffscreenContext() = default;
  // Makes the context current on the calling thread.
  virtual void make_current() = 0;
  // The finished frame, RGBA 8-bit, row 0 at the top (OpenCV's layout). Valid until the
  // next draw; glFinish is called first.
  virtual cv::Mat rgba() = 0;
  virtual int width_px() const = 0;
  virtual int height_px() const = 0;
  virtual std::string describe() const = 0;  // GL vendor/renderer/version
};

// Throws std::runtime_error when no context can be made (the message says which and why).
std::unique_ptr<OffscreenContext> make_offscreen_context(int width_px, int height_px);

}  // namespace arphys::rendering
