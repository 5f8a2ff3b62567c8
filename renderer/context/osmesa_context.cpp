#define GL_GLEXT_PROTOTYPES
#include <GL/osmesa.h>
#include <GL/glcorearb.h>

#include <stdexcept>
#include <vector>

#include "renderer/context/offscreen_context.hpp"

namespace arphys::rendering {

namespace {

class OsMesaContext final : public OffscreenContext {
 public:
  OsMesaContext(int width, int height) : width_(width), height_(height), buffer_(height, width, CV_8UC4) {
    if (width <= 0 || height <= 0 || width > 8192 || height > 8192) {
      throw std::invalid_argument("offscreen context: size " + std::to_string(width) + "x" + std::to_string(height) +
                                  " (expected 1..8192 pixels each way)");
    }
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                              OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_) throw std::runtime_error("OSMesa could not create an OpenGL 3.3 core context (is libosmesa6 installed?)");
    make_current();
  }
  ~OsMesaContext() override {
    if (context_) OSMesaDestroyContext(context_);
  }
  void make_current() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data, GL_UNSIGNED_BYTE, width_, height_)) {
      throw std::runtime_error("OSMesaMakeCurrent failed");
    }
    // Row 0 of the buffer at the top, as OpenCV stores images.
    OSMesaPixelStore(OSMESA_Y_UP, 0);
  }
  cv::Mat rgba() override {
    glFinish();
    return buffer_;
  }
  int width_px() const override { return width_; }
  int height_px() const override { return height_; }
  std::string describe() const override {
    const auto text = [](GLenum name) {
      const GLubyte* s = glGetString(name);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    return "OSMesa " + text(GL_RENDERER) + ", OpenGL " + text(GL_VERSION);
  }

 private:
  int width_, height_;
  cv::Mat buffer_;
  OSMesaContext context_ = nullptr;
};

}  // namespace

std::unique_ptr<OffscreenContext> make_offscreen_context(int width_px, int height_px) {
  return std::make_unique<OsMesaContext>(width_px, height_px);
}

}  // namespace arphys::rendering
