#include "renderer/app/offline_render.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "configs/loader/scene_config.hpp"
#include "renderer/drawing/overlay_renderer.hpp"
#include "renderer/scene/view.hpp"

namespace arphys::rendering {
namespace {

// Bodies at time t_s of a `simulate` CSV (t,id,px,py,pz,qw,qx,qy,qz,...): the rows of the
// last step at or before t_s. A body id "model#n" is drawn with model "model".
std::vector<BodyToDraw> bodies_from_csv(const std::string& path, double t_s, const config::SceneConfig& scene) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read states file " + path);
  std::string line;
  std::getline(in, line);  // header
  std::map<std::string, BodyToDraw> latest;
  static const char* const kColumns[] = {"t", "id", "px", "py", "pz", "qw", "qx", "qy", "qz"};
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::string where = "states file " + path + " line " + std::to_string(line_number);
    std::istringstream row(line);
    std::string field;
    std::vector<std::string> f;
    while (std::getline(row, field, ',')) f.push_back(field);
    if (f.size() < 9)
      throw std::runtime_error(where + ": " + std::to_string(f.size()) + " fields, expected at least 9 (t,id,px,py,pz,qw,qx,qy,qz)");
    const auto number = [&](int column) {
      const char* text = f[column].c_str();
      char* end = nullptr;
      const double value = std::strtod(text, &end);
      if (end == text || *end != '\0' || !std::isfinite(value))
        throw std::runtime_error(where + ": " + kColumns[column] + " is '" + f[column] + "', expected a finite number");
      return value;
    };
    const double t = number(0);
    if (t > t_s + 1e-9) break;
    const std::string model = f[1].substr(0, f[1].find('#'));
    const config::ObjectConfig* object = scene.find_object(model);
    try {
      latest[f[1]] = {model, object && object->role == config::Role::kReal,
                      geometry::make_pose({number(2), number(3), number(4)}, {number(5), number(6), number(7), number(8)},
                                          f[1], 1e-3)};
    } catch (const std::invalid_argument& e) {  // (make_pose: a quaternion too far from unit)
      throw std::runtime_error(where + ": " + e.what());
    }
  }
  if (latest.empty()) throw std::runtime_error("states file " + path + " has no rows at or before t = " + std::to_string(t_s));
  std::vector<BodyToDraw> bodies;
  for (const auto& [id, body] : latest) bodies.push_back(body);
  return bodies;
}

}  // namespace

void render_offline(const CameraProjection& projection, const geometry::Pose& X_WC, const OfflineRequest& request) {
  const std::string& background_path = request.background_path;
  const std::string& out_path = request.out_path;
  const std::vector<std::string>& meshes = request.meshes;
  const std::vector<std::string>& poses = request.poses;
  const cv::Mat background = cv::imread(background_path, cv::IMREAD_COLOR);
  if (background.empty()) throw std::runtime_error("cannot read background image " + background_path);
  if (background.cols != projection.width_px || background.rows != projection.height_px) {
    throw std::runtime_error("background " + background_path + " is " + std::to_string(background.cols) + "x" +
                             std::to_string(background.rows) + " but the camera is " + std::to_string(projection.width_px) +
                             "x" + std::to_string(projection.height_px));
  }
  OverlayRenderer renderer(projection);
  OverlayLayers layers;
  std::unique_ptr<SceneModels> models;
  if (!request.scene_path.empty()) {
    const config::SceneConfig scene = config::load_scene(request.scene_path);
    models = std::make_unique<SceneModels>(scene, renderer);
    std::vector<BodyToDraw> bodies;
    if (!request.states_path.empty()) {
      bodies = bodies_from_csv(request.states_path, request.states_time_s, scene);
    } else {
      for (const auto& o : scene.objects) {
        if (o.role == config::Role::kVirtual && !o.spawn_at_start.empty()) {
          for (const auto& s : o.spawn_at_start) bodies.push_back({o.id, false, s.X_WB});
        } else {
          bodies.push_back({o.id, o.role == config::Role::kReal, o.X_WO});
        }
      }
    }
    int unknown = 0;
    layers = layers_for(*models, bodies, X_WC, request.layers, &unknown);
    if (unknown > 0) std::fprintf(stderr, "renderer: %d bodies of models the scene does not have, skipped\n", unknown);
  }
  if (meshes.size() != poses.size()) throw std::invalid_argument("every --mesh needs one --pose (camera-from-object)");
  for (size_t i = 0; i < meshes.size(); ++i) {
    const GpuMesh* mesh = renderer.upload(geometry::load_mesh(meshes[i]));
    layers.items.push_back({mesh, parse_pose(poses[i], "--pose"), {0.93f, 0.80f, 0.62f, 1.0f}, DrawStyle::kShaded});
  }
  const cv::Mat out = renderer.composite(layers, background);
  if (!cv::imwrite(out_path, out)) throw std::runtime_error("cannot write " + out_path);
  std::fprintf(stderr, "renderer: %zu objects drawn over %s -> %s (%s)\n", layers.items.size(), background_path.c_str(),
               out_path.c_str(), renderer.describe().c_str());
}


}  // namespace arphys::rendering
