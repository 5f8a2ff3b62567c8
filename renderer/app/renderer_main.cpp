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
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <random>

#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "arphys/image_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/frame_order.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "renderer/drawing/overlay_renderer.hpp"
#include "renderer/output/video_file.hpp"
#include "renderer/process/world_state_matcher.hpp"
#include "renderer/scene/scene_models.hpp"
#include "renderer/scene/view.hpp"

namespace {

using namespace arphys;
using namespace arphys::rendering;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

// Logs the first occurrence of each kind of bad input; every one is counted.
struct BadInput {
  std::map<std::string, int64_t> counts;
  void note(const std::string& kind, const std::string& detail) {
    if (counts[kind]++ == 0) std::fprintf(stderr, "renderer: %s (%s); further ones counted silently\n", kind.c_str(), detail.c_str());
  }
  int64_t total() const {
    int64_t n = 0;
    for (const auto& [k, v] : counts) n += v;
    return n;
  }
};

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

int offline(const CameraProjection& projection, const std::string& background_path, const std::string& out_path,
            const std::string& scene_path, const geometry::Pose& X_WC, const std::vector<std::string>& meshes,
            const std::vector<std::string>& poses, const LayerOptions& options, const std::string& states_path,
            double states_time_s) {
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
  if (!scene_path.empty()) {
    const config::SceneConfig scene = config::load_scene(scene_path);
    models = std::make_unique<SceneModels>(scene, renderer);
    std::vector<BodyToDraw> bodies;
    if (!states_path.empty()) {
      bodies = bodies_from_csv(states_path, states_time_s, scene);
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
    layers = layers_for(*models, bodies, X_WC, options, &unknown);
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
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys renderer: virtual objects drawn over camera frames from the camera's viewpoint (OSMesa).\n"
               "Offline with --out; otherwise live on LCM (images + world states in, overlays out)."};
  std::string camera_path, scene_path, background, out, camera_pose, look_at_text, match = "nearest-earlier", url, video,
      png_dir, states_path;
  double states_time_s = 0;
  std::vector<std::string> meshes, poses;
  bool proxies = false, axes = false, overlay_lcm = false, no_contacts = false, window = false;
  std::string spawn_model = "bunny";
  int png_every = 30;
  double duration_s = 0, near_m = 0.01, far_m = 20.0, wait_ms = 0;
  app.add_option("--camera", camera_path, "camera calibration (OpenCV YAML); default: the scene's camera");
  app.add_option("--scene", scene_path, "scene YAML: models of the objects, LCM channels");
  app.add_option("--background", background, "offline: the picture to draw over (the camera's size)");
  app.add_option("--out", out, "offline: write the composited picture here and exit");
  app.add_option("--mesh", meshes, "offline: a mesh file to draw (mesh units taken as metres), repeatable");
  app.add_option("--pose", poses, "offline: \"x y z qw qx qy qz\" camera-from-object for the --mesh of the same rank");
  app.add_option("--camera-pose", camera_pose, "\"x y z qw qx qy qz\": the camera in the world (X_WC, OpenCV axes) "
                                               "when no tracked table gives it; default: 0.9 m in front of and 0.7 m "
                                               "above the world origin, looking at it");
  app.add_option("--look-at", look_at_text, "\"ex ey ez tx ty tz\": the camera at eye E looking at target T "
                                             "(world, metres; z up), instead of --camera-pose");
  app.add_option("--states", states_path, "offline with --scene: draw the bodies of a `simulate` CSV ...");
  app.add_option("--time", states_time_s, "offline: ... at this simulation time, seconds")->capture_default_str();
  app.add_option("--match", match, "live: which world state to draw over a frame: exact (the one computed from that "
                                   "frame), nearest-earlier, latest")->capture_default_str();
  app.add_option("--wait-ms", wait_ms,
                 "live: hold each frame up to this long after it arrives for the world state computed from it (0: draw "
                 "at once with the states that have arrived, which are an earlier frame's). Waiting keeps a moving "
                 "tracked object's overlay on its image, at the cost of the simulator's latency")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--video", video, "live: write the overlay video here (.mp4: mp4v, .avi: MJPG)");
  app.add_option("--png-dir", png_dir, "live: write PNG snapshots here");
  app.add_option("--png-every", png_every, "live: a snapshot every N frames")->capture_default_str();
  app.add_flag("--overlay-lcm", overlay_lcm, "live: publish the overlay as a JPEG image_t on the overlay channel");
  app.add_flag("--window", window, "live: show the overlay in a window (needs a display). Keys: b spawns a "
                                   "--spawn-model thrown onto the table as in the paper, r resets, p pauses/resumes, "
                                   "q quits");
  app.add_option("--spawn-model", spawn_model, "live: the virtual model the b key spawns")->capture_default_str();
  app.add_flag("--proxies", proxies, "draw real objects' collision shapes translucent (debug)");
  app.add_flag("--axes", axes, "draw the world axes (debug)");
  app.add_flag("--no-contacts", no_contacts, "live: do not draw contact points and normals");
  app.add_option("--near", near_m, "near clipping distance, metres")->capture_default_str();
  app.add_option("--far", far_m, "far clipping distance, metres")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL (default: the scene's lcm.url)");
  app.add_option("--duration", duration_s, "live: exit after this many seconds (0: until SIGINT)");
  CLI11_PARSE(app, argc, argv);

  LayerOptions options;
  options.real_proxies = proxies;
  options.world_axes = axes;
  config::SceneConfig scene;
  CameraProjection projection;
  geometry::Pose camera_pose_X_WC = default_camera_pose();
  try {
    if (!scene_path.empty()) scene = config::load_scene(scene_path);
    if (camera_path.empty()) camera_path = scene.camera_file;
    if (camera_path.empty()) throw std::invalid_argument("no camera: give --camera, or a --scene that names one");
    projection = CameraProjection::from_config(config::load_camera(camera_path), near_m, far_m);
    if (!look_at_text.empty()) {
      std::istringstream in(look_at_text);
      double v[6];
      for (double& x : v) {
        if (!(in >> x)) throw std::invalid_argument("--look-at '" + look_at_text + "': expected six numbers");
      }
      camera_pose_X_WC = geometry::look_at({v[0], v[1], v[2]}, {v[3], v[4], v[5]});
    } else if (!camera_pose.empty()) {
      camera_pose_X_WC = parse_pose(camera_pose, "--camera-pose");
    }
    if (!out.empty()) {
      if (background.empty()) throw std::invalid_argument("--out needs --background");
      return offline(projection, background, out, scene_path, camera_pose_X_WC, meshes, poses, options, states_path,
                     states_time_s);
    }
    if (scene_path.empty()) throw std::invalid_argument("live rendering needs --scene (models and channels)");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderer: %s\n", e.what());
    return 2;
  }

  // Live.
  std::unique_ptr<msg::Bus> bus;
  std::unique_ptr<OverlayRenderer> renderer;
  std::unique_ptr<SceneModels> models;
  MatchPolicy policy;
  const geometry::Pose fixed_X_WC = camera_pose_X_WC;
  try {
    policy = match_policy_from(match);
    bus = std::make_unique<msg::Bus>(url.empty() ? scene.lcm_url : url);
    renderer = std::make_unique<OverlayRenderer>(projection);
    models = std::make_unique<SceneModels>(scene, *renderer);
    if (!png_dir.empty()) std::filesystem::create_directories(png_dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderer: %s\n", e.what());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  WorldStateMatcher<arphys::world_state_t> states(64);
  WorldStateMatcher<geometry::Pose> camera_poses(64);
  // The newest frame, and (--wait-ms) the one it superseded while that waited for its own
  // world state, to be drawn at once.
  std::optional<arphys::image_t> pending, superseded;
  std::chrono::steady_clock::time_point pending_arrival;
  BadInput bad;
  msg::FrameOrder frame_order;
  int64_t frames_dropped = 0, past_the_wait = 0;
  // How long the pending frame may still wait for its own world state (ms; 0: draw it now).
  const auto wait_left_ms = [&]() -> double {
    if (!pending || wait_ms <= 0 || policy == MatchPolicy::kLatest || states.has_reached(pending->utime)) return 0;
    return wait_ms - std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - pending_arrival).count();
  };
  // Counts a frame drawn without its own world state though it could have waited for it.
  const auto waited_in_vain = [&](const arphys::image_t& frame) {
    if (wait_ms > 0 && policy != MatchPolicy::kLatest && !states.has_reached(frame.utime)) ++past_the_wait;
  };
  bus->subscribe<arphys::world_state_t>(scene.channels.world_state,
                                        [&](const arphys::world_state_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                          states.add(m.utime, m);
                                        });
  bus->subscribe<arphys::object_poses_t>(scene.channels.object_poses,
                                         [&](const arphys::object_poses_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                           if (!m.camera_world_valid) return;
                                           camera_poses.add(m.utime, msg::from_message(m.X_WC, "X_WC"));
                                         });
  bus->subscribe<arphys::image_t>(scene.channels.camera_image,
                                  [&](const arphys::image_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                    // A frame already handled (re-sent, replayed) or older than one
                                    // is not drawn again: counted, and the video stays in order.
                                    const auto verdict = frame_order.check(m.camera_id, m.seq, m.utime);
                                    if (verdict != msg::FrameOrder::Verdict::kNew) {
                                      bad.note(std::string(msg::to_string(verdict)) + " camera frame",
                                               m.camera_id + " seq " + std::to_string(m.seq));
                                      return;
                                    }
                                    // Keep the newest: latency over completeness. A frame held by the
                                    // wait is drawn, not dropped, unless one is already due.
                                    if (pending && wait_left_ms() > 0 && !superseded) {
                                      superseded = std::move(pending);
                                    } else if (pending) {
                                      ++frames_dropped;
                                    }
                                    pending = m;
                                    pending_arrival = std::chrono::steady_clock::now();
                                  });

  cv::VideoWriter writer;
  if (window && !std::getenv("DISPLAY")) {
    std::fprintf(stderr, "renderer: --window needs a display (DISPLAY is not set); continuing without a window\n");
    window = false;
  }
  int64_t command_seq = 0;
  bool paused = false;
  std::mt19937 spawn_rng(static_cast<uint32_t>(getpid()));
  // The paper's interaction: a key throws a virtual object onto the table from above its
  // near edge, with a small random spread so repeated presses do not stack exactly.
  auto send_command = [&](int8_t command) {
    arphys::sim_command_t c{};
    c.utime = msg::now_utime();
    c.seq = ++command_seq;
    c.sender = std::string("renderer@") + std::to_string(getpid());
    c.command = command;
    if (command == arphys::sim_command_t::COMMAND_SPAWN) {
      std::uniform_real_distribution<double> spread(-0.1, 0.1);
      c.model = spawn_model;
      const geometry::Pose X = geometry::make_pose({spread(spawn_rng), -0.3, 0.3}, {0.7071067811865476, 0.7071067811865476, 0, 0});
      c.X_WB = msg::to_message(X);
      const double v[3] = {spread(spawn_rng), 0.8, 0.5};
      std::copy(v, v + 3, c.v_WB_m_s);
    }
    bus->publish(scene.channels.sim_command, c);
  };
  std::fprintf(stderr, "renderer: scene %s, camera %s (%dx%d), match %s, wait %.0f ms, %s, LCM %s\n", scene.name.c_str(),
               camera_path.c_str(), projection.width_px, projection.height_px, to_string(policy), wait_ms,
               renderer->describe().c_str(), bus->url().c_str());
  const auto start = std::chrono::steady_clock::now();
  auto last_status = start;
  int64_t rendered = 0, rendered_since_status = 0, published = 0, without_world = 0;
  double render_ms_since_status = 0;
  // Draws the world state matched to this frame over it, writes the outputs asked for and
  // publishes its render status.
  const auto draw = [&](const arphys::image_t& message) {
    const int64_t render_start = msg::now_utime();
    cv::Mat frame;
    try {
      frame = msg::decode_image_message(message);
    } catch (const std::exception& e) {
      bad.note("undecodable image", e.what());
    }
    if (!frame.empty() && (frame.cols != projection.width_px || frame.rows != projection.height_px)) {
      bad.note("image of the wrong size", std::to_string(frame.cols) + "x" + std::to_string(frame.rows));
      frame.release();
    }
    if (!frame.empty()) {
      const auto world = states.match(message.utime, policy);
      const auto camera = camera_poses.match(message.utime, MatchPolicy::kNearestEarlier);
      const geometry::Pose X_WC = camera.state ? *camera.state : fixed_X_WC;
      OverlayLayers layers;
      std::string note = "no world state";
      if (world.state) {
        std::vector<BodyToDraw> bodies;
        for (const auto& b : world.state->bodies) {
          const std::string problem = msg::pose_problem(b.X_WB);
          if (!problem.empty()) {
            bad.note("body with a bad pose", b.body_id + ": " + problem);
            continue;
          }
          bodies.push_back({b.model, b.role == arphys::body_state_t::ROLE_REAL, msg::from_message(b.X_WB)});
        }
        int unknown = 0;
        layers = layers_for(*models, bodies, X_WC, options, &unknown);
        for (int i = 0; i < unknown; ++i) bad.note("unknown model in the world state", "not in scene " + scene.name);
        if (!no_contacts) {
          for (const auto& c : world.state->contacts) {
            layers.contacts.push_back({layers.X_CW * msg::from_array(c.p_W_m), layers.X_CW.linear() * msg::from_array(c.n_W)});
          }
        }
        note = "world t=" + std::to_string(world.state->sim_time_s).substr(0, 6) + " s";
      } else {
        ++without_world;
      }
      cv::Mat overlay = renderer->composite(layers, frame);
      const int64_t render_end = msg::now_utime();
      char text[200];
      std::snprintf(text, sizeof text, "render %.1f ms  capture->render %.1f ms  %s", 1e-3 * (render_end - render_start),
                    1e-3 * (render_end - message.utime), note.c_str());
      cv::putText(overlay, text, {8, overlay.rows - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 3, cv::LINE_AA);
      cv::putText(overlay, text, {8, overlay.rows - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {255, 255, 255}, 1, cv::LINE_AA);
      if (!video.empty()) {
        if (!writer.isOpened()) {
          try {
            writer = open_video_file(video, 30, overlay.size(), true);
          } catch (const std::exception& e) {
            bad.note("video file cannot be written", e.what());
          }
        }
        if (writer.isOpened()) writer.write(overlay);
      }
      if (!png_dir.empty() && png_every > 0 && rendered % png_every == 0) {
        cv::imwrite(png_dir + "/overlay_" + std::to_string(message.seq) + ".png", overlay);
      }
      if (overlay_lcm) {
        bus->publish(scene.channels.overlay_image,
                     msg::encode_image_message(overlay, message.utime, message.seq, message.camera_id));
        ++published;
      }
      if (window) {
        cv::imshow("arphys", overlay);
        const int key = cv::waitKey(1) & 0xff;
        if (key == 'q' || key == 27) g_stop = true;
        if (key == 'b') send_command(arphys::sim_command_t::COMMAND_SPAWN);
        if (key == 'r') send_command(arphys::sim_command_t::COMMAND_RESET);
        if (key == 'p') {
          paused = !paused;
          send_command(paused ? arphys::sim_command_t::COMMAND_PAUSE : arphys::sim_command_t::COMMAND_RESUME);
        }
      }
      arphys::render_status_t status{};
      status.utime = message.utime;
      status.seq = message.seq;
      status.world_state_utime = world.state ? world.capture_utime : 0;
      status.world_state_sim_time_s = world.state ? world.state->sim_time_s : 0;
      status.world_state_match = static_cast<int8_t>(world.kind);
      status.render_start_utime = render_start;
      status.render_end_utime = render_end;
      status.publish_utime = msg::now_utime();
      bus->publish(scene.channels.render_status, status);
      ++published;
      ++rendered;
      ++rendered_since_status;
      render_ms_since_status += 1e-3 * (render_end - render_start);
    }
  };
  while (!g_stop) {
    if (duration_s > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > duration_s) break;
    // (While a frame waits, woken by any message, the world state among them, or at its deadline.)
    const double waiting_ms = wait_left_ms();
    bus->handle_timeout_ms(waiting_ms > 0 ? std::clamp(static_cast<int>(std::ceil(waiting_ms)), 1, 20) : 20);
    bus->handle_pending();
    const bool hold = pending && wait_left_ms() > 0;
    if (superseded) {
      // Held for its own world state when a newer frame came: drawn now with what there is.
      const arphys::image_t message = std::move(*superseded);
      superseded.reset();
      waited_in_vain(message);
      draw(message);
    }
    if (pending && !hold) {
      const arphys::image_t message = std::move(*pending);
      pending.reset();
      waited_in_vain(message);
      draw(message);
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_status >= std::chrono::seconds(1)) {
      const double window_s = std::chrono::duration<double>(now - last_status).count();
      arphys::process_status_t status =
          msg::heartbeat("renderer", renderer->describe(), std::chrono::duration<double>(now - start).count(), *bus);
      status.rate_hz = rendered_since_status / window_s;
      status.stage_duration_ms = rendered_since_status ? render_ms_since_status / rendered_since_status : 0.0;
      status.published = published;
      status.dropped = frames_dropped;
      status.decode_errors += bad.counts["undecodable image"];
      status.rejected += bad.total() - bad.counts["undecodable image"];
      status.state = rendered_since_status == 0 ? "waiting for camera frames"
                                                : (states.empty() ? "drawing camera frames only: no world state" : "rendering");
      for (const auto& [kind, count] : bad.counts) msg::add_figure(status, kind, static_cast<double>(count));
      msg::add_figure(status, "frames_without_world_state", static_cast<double>(without_world));
      if (wait_ms > 0) msg::add_figure(status, "frames_past_the_wait", static_cast<double>(past_the_wait));
      bus->publish(scene.channels.process_status, status);
      last_status = now;
      rendered_since_status = 0;
      render_ms_since_status = 0;
    }
  }
  std::fprintf(stderr, "renderer: %lld frames rendered, %lld dropped (newer frame waiting), %lld without a world state, "
               "%lld drawn at the wait's end without their own, %lld bad inputs\n",
               static_cast<long long>(rendered), static_cast<long long>(frames_dropped), static_cast<long long>(without_world),
               static_cast<long long>(past_the_wait), static_cast<long long>(bad.total()));
  return 0;
}
