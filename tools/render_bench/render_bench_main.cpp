// arphys-render-bench: milliseconds per 640x480 overlay frame (draw + read-back +
// composite) against the triangles drawn, on this machine's OpenGL (OSMesa llvmpipe),
// for single meshes of growing size and for the paper's two scenes. Writes
// render_bench.csv to --out.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include <opencv2/imgproc.hpp>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/scene_config.hpp"
#include "renderer/drawing/overlay_renderer.hpp"
#include "renderer/scene/scene_models.hpp"
#include "renderer/scene/view.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace {

using namespace arphys;
using namespace arphys::rendering;
using Clock = std::chrono::steady_clock;

struct Timing {
  double draw_ms = 0, composite_ms = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Timing time_frames(OverlayRenderer& renderer, const OverlayLayers& layers, const cv::Mat& frame, int frames) {
  std::vector<double> draw, composite;
  for (int i = 0; i < frames; ++i) {
    const auto t0 = Clock::now();
    const cv::Mat rgba = renderer.render_rgba(layers);  // includes glFinish: the read-back point
    const auto t1 = Clock::now();
    const cv::Mat out = composite_over(rgba, frame);
    const auto t2 = Clock::now();
    draw.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    composite.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  return {median(draw), median(composite)};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys render benchmark: ms per 640x480 overlay frame against triangle count (OSMesa)."};
  std::string out = ".";
  int frames = 40;
  app.add_option("--out", out, "output directory")->capture_default_str();
  app.add_option("--frames", frames, "frames timed per case (median reported)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::string configs = config::default_config_dir();
  const auto camera = config::load_camera(configs + "/cameras/synthetic_640x480.yaml");
  OverlayRenderer renderer(CameraProjection::from_config(camera));
  cv::Mat frame;
  cv::cvtColor(tracking::clutter_background(640, 480, 5), frame, cv::COLOR_GRAY2BGR);
  std::ofstream csv(out + "/render_bench.csv");
  csv << "case,triangles,draw_ms,composite_ms,total_ms\n";
  std::printf("%-28s %10s %9s %13s %9s\n", "case", "triangles", "draw_ms", "composite_ms", "total_ms");
  auto report = [&](const std::string& name, std::size_t triangles, const OverlayLayers& layers,
                    OverlayRenderer* with = nullptr) {
    const Timing t = time_frames(with ? *with : renderer, layers, frame, frames);
    csv << name << "," << triangles << "," << t.draw_ms << "," << t.composite_ms << "," << t.draw_ms + t.composite_ms << "\n";
    std::printf("%-28s %10zu %9.2f %13.2f %9.2f\n", name.c_str(), triangles, t.draw_ms, t.composite_ms,
                t.draw_ms + t.composite_ms);
    std::fflush(stdout);
  };

  // Single meshes filling about a third of the frame, 0.5 m in front of the camera.
  Eigen::Isometry3d X_CO = Eigen::Isometry3d::Identity();
  X_CO.translation() = Eigen::Vector3d(0, 0, 0.5);
  X_CO.linear() = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  struct Case {
    std::string name;
    geometry::TriangleMesh mesh;
  };
  std::vector<Case> cases;
  cases.push_back({"box", geometry::make_box_mesh({0.2, 0.2, 0.2})});
  for (int s : {1, 2, 3, 4, 5}) cases.push_back({"sphere_subdiv" + std::to_string(s), geometry::make_sphere_mesh(0.12, s)});
  cases.push_back({"bunny_5k", geometry::load_mesh(configs + "/models/stanford-bunny-5k.obj", Eigen::Vector3d::Constant(1.5))});
  cases.push_back({"bunny_70k", geometry::load_mesh(configs + "/models/stanford-bunny-70k.ply", Eigen::Vector3d::Constant(1.5))});
  for (const auto& c : cases) {
    OverlayLayers layers;
    layers.items.push_back({renderer.upload(c.mesh), X_CO, {0.9f, 0.8f, 0.6f, 1.0f}, DrawStyle::kShaded});
    report(c.name, c.mesh.num_triangles(), layers);
  }

  // The paper's scenes as the live renderer draws them (real objects as phantoms); the
  // bunnies once more through a webcam's lens (the example calibration: k1 0.08, k2 -0.19), whose
  // drawing is remapped after GL (LensWarp).
  OverlayRenderer lens_renderer(CameraProjection::from_config(config::load_camera(configs + "/cameras/webcam_640x480_example.yaml")));
  for (const auto& [name, scene_file] : std::vector<std::pair<std::string, std::string>>{
           {"scene_spoon_teacup", "spoon_teacup.yaml"}, {"scene_bunnies20", "bunnies20.yaml"},
           {"scene_bunnies20_lens", "bunnies20.yaml"}}) {
    OverlayRenderer& drawer = name == "scene_bunnies20_lens" ? lens_renderer : renderer;
    const auto scene = config::load_scene(configs + "/scenes/" + scene_file);
    SceneModels models(scene, drawer);
    std::vector<BodyToDraw> bodies;
    std::size_t triangles = 0;
    for (const auto& o : scene.objects) {
      const int copies = o.role == config::Role::kVirtual ? std::max<int>(1, static_cast<int>(o.spawn_at_start.size())) : 1;
      for (int i = 0; i < copies; ++i) {
        geometry::Pose X_WB = o.X_WO;
        if (!o.spawn_at_start.empty()) X_WB = o.spawn_at_start[i].X_WB;
        bodies.push_back({o.id, o.role == config::Role::kReal, X_WB});
        triangles += models.find(o.id)->render_triangles;
      }
    }
    report(name, triangles, layers_for(models, bodies, default_camera_pose(), {}, nullptr), &drawer);
  }
  return 0;
}
