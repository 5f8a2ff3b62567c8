#pragma once
// The renderer offline: one picture of the scene's objects (at their scene poses, or as a
// `simulate` CSV has them at a time) or of given meshes at given poses, over a background.
#include <string>
#include <vector>

#include "renderer/drawing/camera_projection.hpp"
#include "renderer/scene/scene_models.hpp"

namespace arphys::rendering {

struct OfflineRequest {
  std::string background_path, out_path;
  std::string scene_path;                  // may be empty: --mesh pictures only
  std::vector<std::string> meshes, poses;  // one "x y z qw qx qy qz" camera-from-object per mesh
  std::string states_path;                 // a `simulate` CSV; empty: the scene's poses
  double states_time_s = 0;
  LayerOptions layers;
};

// Writes the picture; throws naming the file and what is wrong with it.
void render_offline(const CameraProjection& projection, const geometry::Pose& X_WC, const OfflineRequest& request);

}  // namespace arphys::rendering
