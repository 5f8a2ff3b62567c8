// renderer: draws the virtual objects over camera frames from the camera's viewpoint.
//
// Offline (--out): one picture, `renderer --camera CAMERA.yaml --background IMAGE --out
// OUT.png` with either --scene (objects at their scene poses, seen from --camera-pose)
// or --mesh FILE --pose "x y z qw qx qy qz" pairs (camera-from-object).
//
// Live (no --out): subscribes to camera images, world states and tracked poses on LCM;
// for each frame draws the world state computed from that frame (or the nearest earlier
// one, --match; --wait-ms holds the frame for its own), composites, writes the outputs
// asked for, and publishes a render status.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <sstream>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/scene_config.hpp"
#include "renderer/app/live_renderer.hpp"
#include "renderer/app/offline_render.hpp"

namespace {

using namespace arphys;
using namespace arphys::rendering;

// The camera in the world: --look-at, else --camera-pose, else the default view.
geometry::Pose camera_pose_from(const std::string& look_at_text, const std::string& camera_pose) {
  if (!look_at_text.empty()) {
    std::istringstream in(look_at_text);
    double v[6];
    for (double& x : v) {
      if (!(in >> x)) throw std::invalid_argument("--look-at '" + look_at_text + "': expected six numbers");
    }
    return geometry::look_at({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
  }
  return camera_pose.empty() ? default_camera_pose() : parse_pose(camera_pose, "--camera-pose");
}

void add_offline_options(CLI::App& app, OfflineRequest& offline, std::string& camera_pose, std::string& look_at_text) {
  app.add_option("--background", offline.background_path, "offline: the picture to draw over (the camera's size)");
  app.add_option("--out", offline.out_path, "offline: write the composited picture here and exit");
  app.add_option("--mesh", offline.meshes, "offline: a mesh file to draw (mesh units taken as metres), repeatable");
  app.add_option("--pose", offline.poses, "offline: \"x y z qw qx qy qz\" camera-from-object for the --mesh of the same rank");
  app.add_option("--camera-pose", camera_pose, "\"x y z qw qx qy qz\": the camera in the world (X_WC, OpenCV axes) "
                                               "when no tracked table gives it; default: 0.9 m in front of and 0.7 m "
                                               "above the world origin, looking at it");
  app.add_option("--look-at", look_at_text, "\"ex ey ez tx ty tz\": the camera at eye E looking at target T "
                                             "(world, metres; z up), instead of --camera-pose");
  app.add_option("--states", offline.states_path, "offline with --scene: draw the bodies of a `simulate` CSV ...");
  app.add_option("--time", offline.states_time_s, "offline: ... at this simulation time, seconds")->capture_default_str();
}

void add_live_options(CLI::App& app, LiveOptions& live, std::string& match) {
  app.add_option("--match", match, "live: which world state to draw over a frame: exact (the one computed from that "
                                   "frame), nearest-earlier, latest")->capture_default_str();
  app.add_option("--wait-ms", live.wait_ms,
                 "live: hold each frame up to this long after it arrives for the world state computed from it (0: draw "
                 "at once with the states that have arrived, which are an earlier frame's). Waiting keeps a moving "
                 "tracked object's overlay on its image, at the cost of the simulator's latency")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--video", live.video, "live: write the overlay video here (.mp4: mp4v, .avi: MJPG)");
  app.add_option("--png-dir", live.png_dir, "live: write PNG snapshots here");
  app.add_option("--png-every", live.png_every, "live: a snapshot every N frames")->capture_default_str();
  app.add_flag("--overlay-lcm", live.overlay_lcm, "live: publish the overlay as a JPEG image_t on the overlay channel");
  app.add_flag("--window", live.window, "live: show the overlay in a window (needs a display). Keys: b spawns a "
                                        "--spawn-model thrown onto the table as in the paper, r resets, p pauses/resumes, "
                                        "q quits");
  app.add_option("--spawn-model", live.spawn_model, "live: the virtual model the b key spawns")->capture_default_str();
  app.add_flag("--no-contacts", live.no_contacts, "live: do not draw contact points and normals");
  app.add_option("--lcm-url", live.lcm_url, "LCM URL (default: the scene's lcm.url)");
  app.add_option("--duration", live.duration_s, "live: exit after this many seconds (0: until SIGINT)");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys renderer: virtual objects drawn over camera frames from the camera's viewpoint (OSMesa).\n"
               "Offline with --out; otherwise live on LCM (images + world states in, overlays out)."};
  std::string camera_path, scene_path, camera_pose, look_at_text, match = "nearest-earlier";
  OfflineRequest offline;
  LiveOptions live;
  LayerOptions layers;
  double near_m = 0.01, far_m = 20.0;
  app.add_option("--camera", camera_path, "camera calibration (OpenCV YAML); default: the scene's camera");
  app.add_option("--scene", scene_path, "scene YAML: models of the objects, LCM channels");
  add_offline_options(app, offline, camera_pose, look_at_text);
  add_live_options(app, live, match);
  app.add_flag("--proxies", layers.real_proxies, "draw real objects' collision shapes translucent (debug)");
  app.add_flag("--axes", layers.world_axes, "draw the world axes (debug)");
  app.add_option("--near", near_m, "near clipping distance, metres")->capture_default_str();
  app.add_option("--far", far_m, "far clipping distance, metres")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  config::SceneConfig scene;
  CameraProjection projection;
  try {
    if (!scene_path.empty()) scene = config::load_scene(scene_path);
    if (camera_path.empty()) camera_path = scene.camera_file;
    if (camera_path.empty()) throw std::invalid_argument("no camera: give --camera, or a --scene that names one");
    projection = CameraProjection::from_config(config::load_camera(camera_path), near_m, far_m);
    const geometry::Pose X_WC = camera_pose_from(look_at_text, camera_pose);
    if (!offline.out_path.empty()) {
      if (offline.background_path.empty()) throw std::invalid_argument("--out needs --background");
      offline.scene_path = scene_path;
      offline.layers = layers;
      render_offline(projection, X_WC, offline);
      return 0;
    }
    if (scene_path.empty()) throw std::invalid_argument("live rendering needs --scene (models and channels)");
    live.policy = match_policy_from(match);
    live.camera_path = camera_path;
    live.X_WC_fixed = X_WC;
    live.layers = layers;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderer: %s\n", e.what());
    return 2;
  }
  return run_live(scene, projection, live);
}
