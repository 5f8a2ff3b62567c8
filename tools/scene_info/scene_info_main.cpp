// arphys-scene-info: loads a scene and its camera, loads and checks every mesh,
// computes the mass properties of the dynamic bodies, and (unless --no-lcm) sends the
// scene's initial world state over real LCM and receives it back, timing the round trip.
// It is the end-to-end check of the foundation: configs, models, message contracts, bus.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <Eigen/Eigenvalues>
#include <iostream>

#include "arphys/world_state_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "simulator/scene/scene_world.hpp"
#include "simulator/geometry/mass_properties.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace {

using namespace arphys;

std::string describe_shape(const config::ShapeConfig& shape) {
  char text[256];
  switch (shape.type) {
    case config::ShapeType::kPlane: return "plane (half-space z <= 0)";
    case config::ShapeType::kBox:
      std::snprintf(text, sizeof text, "box %.3f x %.3f x %.3f m", shape.size_m.x(), shape.size_m.y(), shape.size_m.z());
      return text;
    case config::ShapeType::kSphere: std::snprintf(text, sizeof text, "sphere r=%.3f m", shape.radius_m); return text;
    case config::ShapeType::kMesh: {
      const auto mesh = geometry::load_mesh(shape.mesh_path, shape.scale);
      const auto topology = geometry::mesh_topology(mesh);
      const Eigen::Vector3d extent = mesh.bounds().sizes();
      std::snprintf(text, sizeof text, "mesh %s x%.3g: %zu triangles, %zu vertices, %.3f x %.3f x %.3f m, %s",
                    std::filesystem::path(shape.mesh_path).filename().c_str(), shape.scale.x(), mesh.num_triangles(),
                    mesh.num_vertices(), extent.x(), extent.y(), extent.z(),
                    topology.closed() ? "closed"
                                      : (std::to_string(topology.boundary_edges) + " boundary edges").c_str());
      return text;
    }
    case config::ShapeType::kConvexSet: {
      const auto parts = geometry::load_mesh_parts(shape.pieces_path, shape.scale);
      std::size_t vertices = 0;
      for (const auto& part : parts) vertices += part.num_vertices();
      std::snprintf(text, sizeof text, "convex set %s x%.3g: %zu pieces, %zu vertices%s%s",
                    std::filesystem::path(shape.pieces_path).filename().c_str(), shape.scale.x(), parts.size(), vertices,
                    shape.mesh_path.empty() ? "" : ", mass from ",
                    shape.mesh_path.empty() ? "" : std::filesystem::path(shape.mesh_path).filename().c_str());
      return text;
    }
  }
  return "?";
}

arphys::world_state_t initial_world_state(const config::SceneConfig& scene) {
  arphys::world_state_t state{};
  state.scene_name = scene.name;
  for (const auto& object : scene.objects) {
    auto add = [&](const std::string& id, const geometry::Pose& X_WB, const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
      arphys::body_state_t body{};
      body.body_id = id;
      body.model = object.id;
      body.role = object.role == config::Role::kReal ? arphys::body_state_t::ROLE_REAL : arphys::body_state_t::ROLE_VIRTUAL;
      body.motion = static_cast<int8_t>(object.motion);
      body.X_WB = msg::to_message(X_WB);
      msg::to_array(v, body.v_WB_m_s);
      msg::to_array(w, body.w_WB_rad_s);
      state.bodies.push_back(body);
    };
    if (object.spawn_at_start.empty()) {
      add(object.id, object.X_WO, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    } else {
      for (std::size_t i = 0; i < object.spawn_at_start.size(); ++i) {
        const auto& s = object.spawn_at_start[i];
        add(object.id + "#" + std::to_string(i), s.X_WB, s.v_WB_m_s, s.w_WB_rad_s);
      }
    }
  }
  state.num_bodies = static_cast<int32_t>(state.bodies.size());
  return state;
}

int lcm_round_trip(const config::SceneConfig& scene, const std::string& url) {
  msg::Bus publisher(url), subscriber(url);
  bool received = false;
  int64_t sent_utime = 0, received_utime = 0;
  int received_bodies = 0;
  subscriber.subscribe<arphys::world_state_t>(
      scene.channels.world_state, [&](const arphys::world_state_t& state, const lcm::ReceiveBuffer&, const std::string&) {
        if (state.publish_utime != sent_utime) return;  // someone else's traffic on the same bus
        received = true;
        received_utime = msg::now_utime();
        received_bodies = state.num_bodies;
      });
  arphys::world_state_t state = initial_world_state(scene);
  state.publish_utime = sent_utime = msg::now_utime();
  publisher.publish(scene.channels.world_state, state);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (!received && std::chrono::steady_clock::now() < deadline) subscriber.handle_timeout_ms(100);
  if (!received) {
    std::cerr << "LCM: the world state sent on " << scene.channels.world_state << " via " << url
              << " did not come back within 2 s (decode errors: " << subscriber.counters().decode_errors << ")\n";
    return 1;
  }
  std::printf("LCM: world_state_t with %d bodies (%d bytes) sent on %s via %s, received back after %.3f ms\n",
              received_bodies, state.getEncodedSize(), scene.channels.world_state.c_str(), url.c_str(),
              (received_utime - sent_utime) * 1e-3);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Load an arphys scene and its camera, check every model, print what the simulator will see, "
               "and round-trip the initial world state over LCM."};
  std::string scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml";
  std::string url;
  bool no_lcm = false;
  app.add_option("scene", scene_path, "scene YAML file")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL for the round trip (default: the scene's lcm.url)");
  app.add_flag("--no-lcm", no_lcm, "skip the LCM round trip");
  CLI11_PARSE(app, argc, argv);

  try {
    const config::SceneConfig scene = config::load_scene(scene_path);
    std::printf("scene %s  (%s)\n", scene.name.c_str(), scene.file.c_str());
    if (scene.camera_file.empty()) {
      std::printf("camera: none (a headless physics scene)\n");
    } else {
      const config::CameraConfig camera = config::load_camera(scene.camera_file);
      std::printf("camera %s: %dx%d px, fx=%.1f fy=%.1f cx=%.1f cy=%.1f px, %s\n", camera.camera_id.c_str(),
                  camera.width_px, camera.height_px, camera.fx_px, camera.fy_px, camera.cx_px, camera.cy_px,
                  camera.has_distortion() ? "distorted" : "no distortion");
    }
    std::printf("gravity (%.2f, %.2f, %.2f) m/s^2, time step %.4f s\n", scene.gravity_m_s2.x(), scene.gravity_m_s2.y(),
                scene.gravity_m_s2.z(), scene.time_step_s);
    for (const auto& object : scene.objects) {
      std::printf("- %s: %s, %s\n    collision: %s\n", object.id.c_str(), config::to_string(object.role),
                  config::to_string(object.motion), describe_shape(object.collision).c_str());
      if (object.render.type != object.collision.type || object.render.mesh_path != object.collision.mesh_path) {
        std::printf("    render:    %s\n", describe_shape(object.render).c_str());
      }
      if (object.motion == config::Motion::kDynamic) {
        const auto props = arphys::scene::mass_properties_of(object);
        const Eigen::Vector3d principal =
            Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(props.inertia_about_com_kg_m2).eigenvalues();
        std::printf("    mass %.4f kg, volume %.4g m^3, centre of mass (%.4f, %.4f, %.4f) m, principal inertia "
                    "(%.3g, %.3g, %.3g) kg m^2\n",
                    props.mass_kg, props.volume_m3, props.center_of_mass_m.x(), props.center_of_mass_m.y(),
                    props.center_of_mass_m.z(), principal.x(), principal.y(), principal.z());
        std::printf("    spawned at start: %zu, at most %d\n", object.spawn_at_start.size(), object.max_instances);
      }
      if (!object.markers.empty()) {
        std::printf("    markers:");
        for (const auto& m : object.markers) std::printf(" %s:%d (%.3f m)", m.family.c_str(), m.id, m.size_m);
        std::printf("\n");
      }
    }
    if (no_lcm) return 0;
    return lcm_round_trip(scene, url.empty() ? scene.lcm_url : url);
  } catch (const config::ConfigError& e) {
    std::cerr << "configuration error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
