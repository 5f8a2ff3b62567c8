#pragma once
// A camera script (configs/synthetic/*.yaml) played as frames: the scene's real objects,
// shaded, with their markers, along keyframed trajectories, seen by the calibrated camera
// over a seeded background with the script's sensor effects; and the LCM messages a real
// camera pipeline would publish for a frame (image, ground truth, camera info).
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "arphys/ground_truth_t.hpp"
#include "configs/loader/camera_script.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "renderer/drawing/overlay_renderer.hpp"
#include "renderer/scene/scene_models.hpp"
#include "simulator/dynamics/kinematic_trajectory.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace arphys::synthetic {

// Where every real object is at a time: bodies to draw, their markers in the camera, the truth.
struct SceneAt {
  std::vector<rendering::BodyToDraw> bodies;
  std::vector<tracking::MarkerPlacement> markers;
  arphys::ground_truth_t truth{};
};

class ScriptedCamera {
 public:
  // Loads the script, its scene and camera, and the renderer; throws (config::ConfigError
  // or std::exception) naming what is wrong.
  explicit ScriptedCamera(const std::string& script_path);
  const config::CameraScriptConfig& script() const { return script_; }
  const config::CameraConfig& camera() const { return camera_; }
  std::string camera_id() const { return camera_.camera_id.empty() ? "synthetic" : camera_.camera_id; }
  std::string describe() const { return gl_->describe(); }
  // The scripted objects move as a tracked body does in the simulator: screw motion between
  // keyframes, held before the first and after the last.
  SceneAt scene_at(double t_s) const;
  // Frame seq at t_s: bodies shaded over the background, then their markers, then the
  // sensor (noise, blur, exposure), drawn from the script's seeded generator.
  cv::Mat frame(const SceneAt& at, int64_t seq);
  // The first drawing compiles shaders and builds the lens maps (seconds on a loaded
  // machine): a real camera is streaming before its first frame is stamped.
  void warm_up();
  // The script's generator's next number in [0, 1) (whether a frame is dropped).
  double uniform() { return uniform_(rng_); }

 private:
  cv::Mat draw(const SceneAt& at, const tracking::ImageEffects& effects);

  config::CameraScriptConfig script_;
  config::CameraConfig camera_;
  std::unique_ptr<rendering::OverlayRenderer> gl_;
  std::unique_ptr<rendering::SceneModels> models_;
  std::map<std::string, dynamics::KinematicTrajectory> trajectories_;
  tracking::CameraModel marker_camera_;
  cv::Mat background_bgr_;
  std::mt19937 rng_;
  std::normal_distribution<double> gain_noise_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// Publishes a frame as a camera driver does: the image, its ground truth and, once a
// second (every frame_rate_hz-th), the camera's intrinsics.
void publish_frame(msg::Bus& bus, const ScriptedCamera& camera, const cv::Mat& frame, SceneAt& at,
                   int64_t capture_utime, int64_t seq, int jpeg_quality);

}  // namespace arphys::synthetic
