#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"

namespace arphys::config {

// What the synthetic camera plays: a scene seen from a camera pose while its real
// objects move along keyframed trajectories (screw-interpolated), with seeded realism
// knobs. Lets the paper's applications run without a person, and gives ground truth.
struct CameraEffectsConfig {
  double noise_sigma = 2.0;        // additive Gaussian sensor noise, grey levels
  double motion_blur_px = 0.0;     // linear motion blur length, pixels, in a seeded direction per frame
  double exposure_jitter = 0.0;    // relative std of a per-frame gain (0.05 = 5 %)
  double drop_rate = 0.0;          // fraction of frames not delivered (captured, never published)
  double delay_ms = 0.0;           // capture-to-publish delay
  uint32_t seed = 1;
};

struct CameraScriptConfig {
  std::string file;
  SceneConfig scene;
  geometry::Pose X_WC = geometry::Pose::Identity();  // camera in the world, OpenCV axes
  double frame_rate_hz = 30.0;                       // 5 .. 60
  double duration_s = 10.0;
  CameraEffectsConfig effects;
  // Keyframes per real object id; objects without keep their scene pose.
  std::map<std::string, std::vector<TimedPoseConfig>> trajectories;
};

// Throws ConfigError (file, line, key, value, expectation) on a bad file; the scene it
// names is loaded and checked too, and every trajectory must name a real object of it.
CameraScriptConfig load_camera_script(const std::string& path);

}  // namespace arphys::config
