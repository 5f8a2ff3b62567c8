#pragma once
// The live renderer: camera images, world states and tracked poses in on LCM; for each
// frame the world state computed from it (or the nearest earlier one) drawn over it; the
// overlay written to the outputs asked for and a render status published per frame.
#include <string>

#include "configs/loader/scene_config.hpp"
#include "renderer/drawing/camera_projection.hpp"
#include "renderer/process/world_state_matcher.hpp"
#include "renderer/scene/scene_models.hpp"
#include "renderer/scene/view.hpp"

namespace arphys::rendering {

struct LiveOptions {
  std::string lcm_url;  // empty: the scene's
  std::string camera_path;
  MatchPolicy policy = MatchPolicy::kNearestEarlier;
  double wait_ms = 0;
  std::string video, png_dir;
  int png_every = 30;
  bool overlay_lcm = false, no_contacts = false, window = false;
  std::string spawn_model = "bunny";
  double duration_s = 0;  // 0: until SIGINT or SIGTERM
  geometry::Pose X_WC_fixed = geometry::Pose::Identity();  // the camera when no tracked table gives it
  LayerOptions layers;
};

// Runs until the duration, a signal or the window's q key. Returns the exit code (2: the
// bus or the models cannot be set up; the reason is printed).
int run_live(const config::SceneConfig& scene, const CameraProjection& projection, const LiveOptions& options);

}  // namespace arphys::rendering
