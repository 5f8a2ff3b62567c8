#include "tools/synthetic_camera/scripted_camera.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "arphys/camera_info_t.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::synthetic {

namespace {

config::CameraScriptConfig load_script(const std::string& path) {
  config::CameraScriptConfig script = config::load_camera_script(path);
  if (script.scene.camera_file.empty()) throw std::invalid_argument(script.scene.file + " names no camera");
  return script;
}

}  // namespace

ScriptedCamera::ScriptedCamera(const std::string& script_path)
    : script_(load_script(script_path)),
      camera_(config::load_camera(script_.scene.camera_file)),
      marker_camera_(tracking::CameraModel::from_config(camera_)),
      rng_(script_.effects.seed),
      gain_noise_(0.0, script_.effects.exposure_jitter) {
  // The bodies are drawn pinhole: the marker renderer takes the whole frame through the
  // camera's lens, once (drawn through it here as well, the bodies would be bent twice and
  // the markers' quiet zones would not match the faces around them).
  rendering::CameraProjection pinhole = rendering::CameraProjection::from_config(camera_);
  pinhole.distortion.clear();
  gl_ = std::make_unique<rendering::OverlayRenderer>(pinhole);
  models_ = std::make_unique<rendering::SceneModels>(script_.scene, *gl_);
  for (const auto& [id, keys] : script_.trajectories)
    for (const auto& key : keys) trajectories_[id].add(key.t_s, key.X_WO);
  const cv::Mat background =
      tracking::clutter_background(camera_.width_px, camera_.height_px, script_.effects.seed + 1000);
  cv::cvtColor(background, background_bgr_, cv::COLOR_GRAY2BGR);
}

SceneAt ScriptedCamera::scene_at(double t_s) const {
  const geometry::Pose X_CW = script_.X_WC.inverse();
  SceneAt at;
  for (const auto& object : script_.scene.objects) {
    if (object.role != config::Role::kReal) continue;
    const auto path = trajectories_.find(object.id);
    const geometry::Pose X_WO = path == trajectories_.end() ? object.X_WO : path->second.pose_at(t_s);
    at.bodies.push_back({object.id, false, X_WO});
    for (const auto& m : object.markers) at.markers.push_back({m.family, m.id, m.size_m, X_CW * X_WO * m.X_OM});
    at.truth.object_ids.push_back(object.id);
    at.truth.X_WO.push_back(msg::to_message(X_WO));
  }
  return at;
}

cv::Mat ScriptedCamera::draw(const SceneAt& at, const tracking::ImageEffects& effects) {
  rendering::OverlayLayers layers = rendering::layers_for(*models_, at.bodies, script_.X_WC, {}, nullptr);
  for (auto& item : layers.items) item.rgba = Eigen::Vector4f(0.78f, 0.76f, 0.72f, 1.0f);
  cv::Mat shaded = gl_->composite(layers, background_bgr_), grey;
  cv::cvtColor(shaded, grey, cv::COLOR_BGR2GRAY);
  return tracking::render_markers(marker_camera_, at.markers, grey, effects);
}

void ScriptedCamera::warm_up() { draw(scene_at(0.0), tracking::ImageEffects{}); }

cv::Mat ScriptedCamera::frame(const SceneAt& at, int64_t seq) {
  tracking::ImageEffects effects;
  effects.noise_sigma = script_.effects.noise_sigma;
  effects.blur_length_px = script_.effects.motion_blur_px;
  effects.blur_angle_rad = uniform_(rng_) * M_PI;
  effects.seed = static_cast<uint32_t>(script_.effects.seed * 100003u + static_cast<uint32_t>(seq));
  cv::Mat frame = draw(at, effects);
  if (script_.effects.exposure_jitter > 0) frame.convertTo(frame, CV_8U, std::max(0.2, 1.0 + gain_noise_(rng_)));
  return frame;
}

void publish_frame(msg::Bus& bus, const ScriptedCamera& camera, const cv::Mat& frame, SceneAt& at,
                   int64_t capture_utime, int64_t seq, int jpeg_quality) {
  const config::CameraScriptConfig& script = camera.script();
  const std::string camera_id = camera.camera_id();
  bus.publish(script.scene.channels.camera_image,
              msg::encode_image_message(frame, capture_utime, seq, camera_id, jpeg_quality));
  arphys::ground_truth_t& truth = at.truth;
  truth.utime = capture_utime;
  truth.seq = seq;
  truth.camera_id = camera_id;
  truth.X_WC = msg::to_message(script.X_WC);
  truth.num_objects = static_cast<int32_t>(truth.object_ids.size());
  bus.publish(script.scene.channels.ground_truth, truth);
  if (seq % static_cast<int64_t>(std::max(1.0, script.frame_rate_hz)) != 0) return;
  const config::CameraConfig& c = camera.camera();
  arphys::camera_info_t info{};
  info.utime = msg::now_utime();
  info.camera_id = camera_id;
  info.width = c.width_px;
  info.height = c.height_px;
  info.fx_px = c.fx_px;
  info.fy_px = c.fy_px;
  info.cx_px = c.cx_px;
  info.cy_px = c.cy_px;
  info.distortion = c.distortion;
  info.num_distortion = static_cast<int32_t>(c.distortion.size());
  bus.publish(script.scene.channels.camera_info, info);
}

}  // namespace arphys::synthetic
