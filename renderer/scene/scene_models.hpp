#pragma once
#include <map>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "renderer/drawing/overlay_renderer.hpp"

namespace arphys::rendering {

// The scene's objects as GPU meshes, uploaded once: each object's render shape (what
// is drawn) and its collision shape (drawn as the translucent proxy of a real object).
// "Model no more than a scene needs": the two are separate, and a scene picks each
// one's resolution. Planes are drawn as a 4 m square.
class SceneModels {
 public:
  // Throws std::runtime_error naming the object and the mesh file when one cannot load.
  SceneModels(const config::SceneConfig& scene, OverlayRenderer& renderer);

  struct Model {
    const GpuMesh* render = nullptr;
    const GpuMesh* collision = nullptr;
    bool real = false;
    Eigen::Vector4f rgba{0.8f, 0.8f, 0.8f, 1.0f};
    std::size_t render_triangles = 0;
  };
  // nullptr for a model id the scene does not have.
  const Model* find(const std::string& model) const;

 private:
  std::map<std::string, Model> models_;
};

// One body to draw: its model (the scene object it instantiates) and pose in the world.
struct BodyToDraw {
  std::string model;
  bool real = false;
  geometry::Pose X_WB = geometry::Pose::Identity();
};

struct LayerOptions {
  bool real_proxies = false;  // translucent collision shapes of real objects
  double proxy_opacity = 0.35;
  bool world_axes = false;
};

// Draw items for bodies seen by a camera at X_WC: virtual bodies shaded, real ones as
// phantoms (and proxies). Bodies of unknown models are skipped and counted.
OverlayLayers layers_for(const SceneModels& models, const std::vector<BodyToDraw>& bodies, const geometry::Pose& X_WC,
                         const LayerOptions& options, int* unknown_models);

}  // namespace arphys::rendering
