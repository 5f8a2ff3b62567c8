#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "renderer/drawing/overlay_renderer.hpp"

namespace arphys::rendering {

namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 clip_from_object;
uniform mat4 eye_from_object;
out vec3 normal_eye;
out vec3 position_eye;
void main() {
  position_eye = (eye_from_object * vec4(position, 1.0)).xyz;
  normal_eye = mat3(eye_from_object) * normal;
  gl_Position = clip_from_object * vec4(position, 1.0);
}
)";

// A headlight at the camera: what faces the camera is bright, grazing faces darken,
// which reads the shape without a scene light to configure. Two-sided (soups).
const char* kFragmentShader = R"(#version 330 core
in vec3 normal_eye;
in vec3 position_eye;
uniform vec4 colour;
uniform int lit;
out vec4 fragment;
void main() {
  vec3 c = colour.rgb;
  if (lit != 0) {
    float facing = abs(dot(normalize(normal_eye), normalize(-position_eye)));
    c *= 0.3 + 0.7 * facing;
  }
  fragment = vec4(c * colour.a, colour.a);
}
)";

unsigned compile(GLenum type, const char* source) {
  const unsigned shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("overlay shader does not compile: ") + log);
  }
  return shader;
}

}  // namespace

OverlayRenderer::OverlayRenderer(const CameraProjection& projection, std::unique_ptr<OffscreenContext> context)
    : projection_(projection), lens_(projection), context_(std::move(context)) {
  const CameraProjection& canvas = lens_.canvas();
  if (!context_) context_ = make_offscreen_context(canvas.width_px, canvas.height_px);
  if (context_->width_px() != canvas.width_px || context_->height_px() != canvas.height_px) {
    throw std::invalid_argument("overlay renderer: context size differs from the drawing canvas's");
  }
  context_->make_current();
  const unsigned vs = compile(GL_VERTEX_SHADER, kVertexShader), fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("overlay shader program does not link");
  u_clip_from_object_ = glGetUniformLocation(program_, "clip_from_object");
  u_eye_from_object_ = glGetUniformLocation(program_, "eye_from_object");
  u_colour_ = glGetUniformLocation(program_, "colour");
  u_lit_ = glGetUniformLocation(program_, "lit");
  glGenVertexArrays(1, &line_vao_);
  glGenBuffers(1, &line_buffer_);
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_buffer_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glVertexAttrib3f(1, 0, 0, 1);
  glBindVertexArray(0);
  glViewport(0, 0, canvas.width_px, canvas.height_px);
}

OverlayRenderer::~OverlayRenderer() {
  context_->make_current();
  meshes_.clear();
  glDeleteBuffers(1, &line_buffer_);
  glDeleteVertexArrays(1, &line_vao_);
  glDeleteProgram(program_);
}

const GpuMesh* OverlayRenderer::upload(const geometry::TriangleMesh& mesh) {
  context_->make_current();
  meshes_.push_back(std::make_unique<GpuMesh>(mesh));
  return meshes_.back().get();
}

void OverlayRenderer::draw_lines(const std::vector<Eigen::Vector3f>& points_C, const Eigen::Vector4f& rgba, bool as_points) {
  if (points_C.empty()) return;
  const Eigen::Matrix4f eye_from_camera = CameraProjection::eye_from_camera();
  const Eigen::Matrix4f clip = lens_.canvas().clip_from_eye() * eye_from_camera;
  glUniformMatrix4fv(u_clip_from_object_, 1, GL_FALSE, clip.data());
  glUniformMatrix4fv(u_eye_from_object_, 1, GL_FALSE, eye_from_camera.data());
  glUniform4fv(u_colour_, 1, rgba.data());
  glUniform1i(u_lit_, 0);
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_buffer_);
  glBufferData(GL_ARRAY_BUFFER, points_C.size() * sizeof(Eigen::Vector3f), points_C.data(), GL_STREAM_DRAW);
  glDrawArrays(as_points ? GL_POINTS : GL_LINES, 0, static_cast<GLsizei>(points_C.size()));
  glBindVertexArray(0);
}

cv::Mat OverlayRenderer::render_rgba(const OverlayLayers& layers) {
  context_->make_current();
  glUseProgram(program_);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);  // meshes may be open soups
  glDisable(GL_BLEND);
  const Eigen::Matrix4f clip_from_eye = lens_.canvas().clip_from_eye();
  const Eigen::Matrix4f eye_from_camera = CameraProjection::eye_from_camera();
  auto draw = [&](const DrawItem& item) {
    const Eigen::Matrix4f eye_from_object = eye_from_camera * item.X_CO.matrix().cast<float>();
    const Eigen::Matrix4f clip_from_object = clip_from_eye * eye_from_object;
    glUniformMatrix4fv(u_clip_from_object_, 1, GL_FALSE, clip_from_object.data());
    glUniformMatrix4fv(u_eye_from_object_, 1, GL_FALSE, eye_from_object.data());
    const Eigen::Vector4f colour = item.style == DrawStyle::kShaded ? Eigen::Vector4f(item.rgba.x(), item.rgba.y(), item.rgba.z(), 1.0f)
                                                                    : item.rgba;
    glUniform4fv(u_colour_, 1, colour.data());
    glUniform1i(u_lit_, 1);
    item.mesh->draw();
  };
  // 1. Real objects write depth only: the camera already shows them.
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  for (const auto& item : layers.items) {
    if (item.style == DrawStyle::kPhantom && item.mesh) draw(item);
  }
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  // 2. Virtual objects.
  for (const auto& item : layers.items) {
    if (item.style == DrawStyle::kShaded && item.mesh) draw(item);
  }
  // 3. Translucent proxies over them, premultiplied "over" blending, no depth writes.
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  for (const auto& item : layers.items) {
    if (item.style == DrawStyle::kTranslucent && item.mesh) draw(item);
  }
  // 4. Debug layers on top of everything.
  glDisable(GL_DEPTH_TEST);
  if (!layers.contacts.empty()) {
    std::vector<Eigen::Vector3f> points, normals;
    for (const auto& c : layers.contacts) {
      points.push_back(c.p_C.cast<float>());
      normals.push_back(c.p_C.cast<float>());
      normals.push_back((c.p_C + layers.contact_normal_length_m * c.n_C).cast<float>());
    }
    glPointSize(7.0f);
    draw_lines(points, Eigen::Vector4f(1.0f, 0.15f, 0.1f, 1.0f), true);
    draw_lines(normals, Eigen::Vector4f(1.0f, 0.9f, 0.1f, 1.0f), false);
  }
  if (layers.draw_world_axes) {
    const Eigen::Vector3f o = (layers.X_CW * Eigen::Vector3d::Zero()).cast<float>();
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3f tip = (layers.X_CW * (layers.axes_length_m * Eigen::Vector3d::Unit(axis))).cast<float>();
      Eigen::Vector4f colour(0, 0, 0, 1);
      colour[axis] = 1.0f;
      draw_lines({o, tip}, colour, false);
    }
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  return lens_.apply(context_->rgba());
}

cv::Mat OverlayRenderer::composite(const OverlayLayers& layers, const cv::Mat& frame) {
  if (frame.cols != projection_.width_px || frame.rows != projection_.height_px ||
      (frame.type() != CV_8UC3 && frame.type() != CV_8UC1)) {
    throw std::invalid_argument("overlay: frame " + std::to_string(frame.cols) + "x" + std::to_string(frame.rows) +
                                " does not match the camera's " + std::to_string(projection_.width_px) + "x" +
                                std::to_string(projection_.height_px) + " 8-bit BGR or grey");
  }
  return composite_over(render_rgba(layers), frame);
}

cv::Mat composite_over(const cv::Mat& rgba, const cv::Mat& frame) {
  CV_Assert(rgba.type() == CV_8UC4 && rgba.size() == frame.size());
  cv::Mat bgr;
  if (frame.type() == CV_8UC1) {
    cv::cvtColor(frame, bgr, cv::COLOR_GRAY2BGR);
  } else {
    bgr = frame.clone();
  }
  for (int y = 0; y < bgr.rows; ++y) {
    const uint8_t* src = rgba.ptr<uint8_t>(y);
    uint8_t* dst = bgr.ptr<uint8_t>(y);
    for (int x = 0; x < bgr.cols; ++x, src += 4, dst += 3) {
      const int a = src[3];
      if (a == 0) continue;
      const int keep = 255 - a;
      // Premultiplied: out = C + (1 - A) * frame, rounded.
      dst[0] = static_cast<uint8_t>(std::min(255, src[2] + (keep * dst[0] + 127) / 255));
      dst[1] = static_cast<uint8_t>(std::min(255, src[1] + (keep * dst[1] + 127) / 255));
      dst[2] = static_cast<uint8_t>(std::min(255, src[0] + (keep * dst[2] + 127) / 255));
    }
  }
  return bgr;
}

}  // namespace arphys::rendering
