#include "renderer/scene/scene_models.hpp"

#include <stdexcept>

namespace arphys::rendering {

namespace {

geometry::TriangleMesh mesh_of(const config::ShapeConfig& shape) {
  switch (shape.type) {
    case config::ShapeType::kBox: return geometry::make_box_mesh(shape.size_m);
    case config::ShapeType::kSphere: return geometry::make_sphere_mesh(shape.radius_m, 3);
    case config::ShapeType::kMesh: return geometry::load_mesh(shape.mesh_path, shape.scale);
    case config::ShapeType::kConvexSet: return geometry::load_mesh(shape.pieces_path, shape.scale);  // the hulls
    case config::ShapeType::kPlane: {
      // The half-space z <= 0: its top face as a thin slab.
      geometry::TriangleMesh slab = geometry::make_box_mesh({4.0, 4.0, 0.002});
      for (auto& v : slab.vertices_m) v.z() -= 0.001;
      return slab;
    }
  }
  throw std::logic_error("unknown shape type");
}

// Distinct, light colours for virtual models, in scene order.
const Eigen::Vector4f kPalette[] = {{0.93f, 0.80f, 0.62f, 1}, {0.55f, 0.75f, 0.95f, 1}, {0.95f, 0.55f, 0.50f, 1},
                                    {0.60f, 0.90f, 0.60f, 1}, {0.85f, 0.70f, 0.95f, 1}};

}  // namespace

SceneModels::SceneModels(const config::SceneConfig& scene, OverlayRenderer& renderer) {
  int virtual_index = 0;
  for (const auto& object : scene.objects) {
    Model model;
    model.real = object.role == config::Role::kReal;
    try {
      const geometry::TriangleMesh render = mesh_of(object.render);
      model.render = renderer.upload(render);
      model.render_triangles = render.num_triangles();
      // A plane's proxy would be a 4 m sheet over everything: real planes get none.
      if (object.collision.type != config::ShapeType::kPlane) model.collision = renderer.upload(mesh_of(object.collision));
    } catch (const std::exception& e) {
      throw std::runtime_error("scene " + scene.file + ", object '" + object.id + "': " + e.what());
    }
    model.rgba = model.real ? Eigen::Vector4f(0.3f, 0.9f, 0.4f, 1.0f) : kPalette[virtual_index++ % 5];
    models_[object.id] = model;
  }
}

const SceneModels::Model* SceneModels::find(const std::string& model) const {
  const auto it = models_.find(model);
  return it == models_.end() ? nullptr : &it->second;
}

OverlayLayers layers_for(const SceneModels& models, const std::vector<BodyToDraw>& bodies, const geometry::Pose& X_WC,
                         const LayerOptions& options, int* unknown_models) {
  OverlayLayers layers;
  const geometry::Pose X_CW = X_WC.inverse();
  layers.X_CW = X_CW;
  layers.draw_world_axes = options.world_axes;
  for (const auto& body : bodies) {
    const SceneModels::Model* model = models.find(body.model);
    if (!model) {
      if (unknown_models) ++*unknown_models;
      continue;
    }
    const geometry::Pose X_CB = X_CW * body.X_WB;
    if (body.real) {
      layers.items.push_back({model->render, X_CB, model->rgba, DrawStyle::kPhantom});
      if (options.real_proxies && model->collision) {
        Eigen::Vector4f rgba = model->rgba;
        rgba.w() = static_cast<float>(options.proxy_opacity);
        layers.items.push_back({model->collision, X_CB, rgba, DrawStyle::kTranslucent});
      }
    } else {
      layers.items.push_back({model->render, X_CB, model->rgba, DrawStyle::kShaded});
    }
  }
  return layers;
}

}  // namespace arphys::rendering
