// arphys-synthetic-camera: the embedded default camera and the ground truth for accuracy.
// Plays a camera script (configs/synthetic/*.yaml): the scene's real objects, shaded,
// with their markers (textured from libapriltag's / OpenCV's own marker images), moving
// along keyframed trajectories, seen by the calibrated camera over a seeded background,
// with seeded sensor noise, motion blur, exposure changes, dropped frames and a
// capture-to-publish delay. Publishes image_t, camera_info_t and ground_truth_t on LCM
// (real time, or as fast as it renders with --fast) and can write the same frames to a
// video file or an image folder, so the tracker's file sources see identical frames.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <thread>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "arphys/camera_info_t.hpp"
#include "arphys/ground_truth_t.hpp"
#include "arphys/image_t.hpp"
#include "configs/loader/camera_script.hpp"
#include "configs/loader/config_error.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "renderer/drawing/overlay_renderer.hpp"
#include "renderer/output/video_file.hpp"
#include "renderer/scene/scene_models.hpp"
#include "simulator/dynamics/kinematic_trajectory.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace {

using namespace arphys;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys synthetic camera: a scripted scene rendered with its markers, published on LCM with ground\n"
               "truth, and/or written to a video file or an image folder."};
  std::string script_path = config::default_config_dir() + "/synthetic/box_push.yaml";
  std::string url, video, folder;
  bool fast = false, no_lcm = false;
  int jpeg_quality = 90;
  int64_t max_frames = 0;
  double duration_s = 0;
  app.add_option("script", script_path, "camera script YAML (scene, camera pose, frame rate, effects, trajectories)")
      ->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL (default: the scene's lcm.url)");
  app.add_flag("--no-lcm", no_lcm, "publish nothing (files only)");
  app.add_flag("--fast", fast, "as fast as it renders, capture times still spaced by the frame period");
  app.add_option("--video", video, "also write the frames here (.avi: MJPG, .mp4: mp4v)");
  app.add_option("--folder", folder, "also write the frames here as frame_NNNNNN.png");
  app.add_option("--jpeg-quality", jpeg_quality, "JPEG quality of published images; 0 publishes raw GRAY8 (mind the "
                                                 "socket buffer: net.core.rmem_max)")
      ->check(CLI::Range(0, 100))->capture_default_str();
  app.add_option("--duration", duration_s, "seconds to play (default: the script's duration_s)");
  app.add_option("--frames", max_frames, "stop after this many frames (0: no limit)");
  CLI11_PARSE(app, argc, argv);

  config::CameraScriptConfig script;
  config::CameraConfig camera;
  std::unique_ptr<rendering::OverlayRenderer> gl;
  std::unique_ptr<rendering::SceneModels> models;
  std::unique_ptr<msg::Bus> bus;
  try {
    script = config::load_camera_script(script_path);
    if (script.scene.camera_file.empty()) throw std::invalid_argument(script.scene.file + " names no camera");
    camera = config::load_camera(script.scene.camera_file);
    // The bodies are drawn pinhole: the marker renderer takes the whole frame through the
    // camera's lens, once (drawn through it here as well, the bodies were bent twice and
    // the markers' quiet zones no longer matched the faces around them).
    rendering::CameraProjection pinhole = rendering::CameraProjection::from_config(camera);
    pinhole.distortion.clear();
    gl = std::make_unique<rendering::OverlayRenderer>(pinhole);
    models = std::make_unique<rendering::SceneModels>(script.scene, *gl);
    if (!no_lcm) bus = std::make_unique<msg::Bus>(url.empty() ? script.scene.lcm_url : url);
    if (!folder.empty()) std::filesystem::create_directories(folder);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-synthetic-camera: %s\n", e.what());
    return 2;
  }
  if (duration_s <= 0) duration_s = script.duration_s;
  // The scripted objects move as a tracked body does in the simulator: screw motion
  // between keyframes, held before the first and after the last.
  std::map<std::string, dynamics::KinematicTrajectory> trajectories;
  for (const auto& [id, keys] : script.trajectories) {
    for (const auto& key : keys) trajectories[id].add(key.t_s, key.X_WO);
  }
  const auto marker_camera = tracking::CameraModel::from_config(camera);
  const cv::Mat background = tracking::clutter_background(camera.width_px, camera.height_px, script.effects.seed + 1000);
  cv::Mat background_bgr;
  cv::cvtColor(background, background_bgr, cv::COLOR_GRAY2BGR);
  std::mt19937 rng(script.effects.seed);
  std::normal_distribution<double> gain_noise(0.0, script.effects.exposure_jitter);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  cv::VideoWriter writer;
  const std::string camera_id = camera.camera_id.empty() ? "synthetic" : camera.camera_id;
  const double period_s = 1.0 / script.frame_rate_hz;

  // Where every real object is at t: drawn bodies, their markers in the camera, the truth.
  struct SceneAt {
    std::vector<rendering::BodyToDraw> bodies;
    std::vector<tracking::MarkerPlacement> markers;
    arphys::ground_truth_t truth{};
  };
  const geometry::Pose X_CW = script.X_WC.inverse();
  auto scene_at = [&](double t_s) {
    SceneAt at;
    for (const auto& object : script.scene.objects) {
      if (object.role != config::Role::kReal) continue;
      const auto path = trajectories.find(object.id);
      const geometry::Pose X_WO = path == trajectories.end() ? object.X_WO : path->second.pose_at(t_s);
      at.bodies.push_back({object.id, false, X_WO});
      for (const auto& m : object.markers) at.markers.push_back({m.family, m.id, m.size_m, X_CW * X_WO * m.X_OM});
      at.truth.object_ids.push_back(object.id);
      at.truth.X_WO.push_back(msg::to_message(X_WO));
    }
    return at;
  };
  // Bodies shaded over the background (real objects are what this camera sees), then
  // their markers, then the sensor.
  auto draw = [&](const SceneAt& at, tracking::ImageEffects effects) {
    rendering::OverlayLayers layers = rendering::layers_for(*models, at.bodies, script.X_WC, {}, nullptr);
    for (auto& item : layers.items) item.rgba = Eigen::Vector4f(0.78f, 0.76f, 0.72f, 1.0f);
    cv::Mat shaded = gl->composite(layers, background_bgr), grey;
    cv::cvtColor(shaded, grey, cv::COLOR_BGR2GRAY);
    return tracking::render_markers(marker_camera, at.markers, grey, effects);
  };
  // A real camera is streaming before its first frame is stamped. The first drawing
  // compiles shaders and builds the lens maps (seconds on a loaded machine): done before
  // the clock starts, else every frame were published that much after its stamp.
  draw(scene_at(0.0), tracking::ImageEffects{});
  const int64_t start_utime = msg::now_utime();
  const auto start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "arphys-synthetic-camera: %s, %s, %.0f FPS for %.1f s%s\n", script.file.c_str(),
               gl->describe().c_str(), script.frame_rate_hz, duration_s, fast ? " (fast)" : "");
  int64_t published = 0, dropped = 0, frame_count = 0;
  auto last_progress = start;
  for (int64_t seq = 0;; ++seq) {
    const double t_s = seq * period_s;
    if (t_s > duration_s || (max_frames > 0 && seq >= max_frames)) break;
    if (!fast) std::this_thread::sleep_until(start + std::chrono::duration<double>(t_s));
    const int64_t capture_utime = start_utime + static_cast<int64_t>(std::llround(t_s * 1e6));

    SceneAt at = scene_at(t_s);
    tracking::ImageEffects effects;
    effects.noise_sigma = script.effects.noise_sigma;
    effects.blur_length_px = script.effects.motion_blur_px;
    effects.blur_angle_rad = uniform(rng) * M_PI;
    effects.seed = static_cast<uint32_t>(script.effects.seed * 100003u + static_cast<uint32_t>(seq));
    cv::Mat frame = draw(at, effects);
    if (script.effects.exposure_jitter > 0) frame.convertTo(frame, CV_8U, std::max(0.2, 1.0 + gain_noise(rng)));
    ++frame_count;

    if (!video.empty()) {
      if (!writer.isOpened()) {
        try {
          writer = rendering::open_video_file(video, script.frame_rate_hz, frame.size(), false);
        } catch (const std::exception& e) {
          std::fprintf(stderr, "arphys-synthetic-camera: %s\n", e.what());
          return 2;
        }
      }
      writer.write(frame);
    }
    if (!folder.empty()) {
      char name[64];
      std::snprintf(name, sizeof name, "/frame_%06lld.png", static_cast<long long>(seq));
      cv::imwrite(folder + name, frame);
    }
    if (bus) {
      if (uniform(rng) < script.effects.drop_rate) {
        ++dropped;
      } else {
        if (!fast && script.effects.delay_ms > 0) {
          std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(script.effects.delay_ms));
        }
        arphys::ground_truth_t& truth = at.truth;
        bus->publish(script.scene.channels.camera_image,
                     msg::encode_image_message(frame, capture_utime, seq, camera_id, jpeg_quality));
        truth.utime = capture_utime;
        truth.seq = seq;
        truth.camera_id = camera_id;
        truth.X_WC = msg::to_message(script.X_WC);
        truth.num_objects = static_cast<int32_t>(truth.object_ids.size());
        bus->publish(script.scene.channels.ground_truth, truth);
        if (seq % static_cast<int64_t>(std::max(1.0, script.frame_rate_hz)) == 0) {
          arphys::camera_info_t info{};
          info.utime = msg::now_utime();
          info.camera_id = camera_id;
          info.width = camera.width_px;
          info.height = camera.height_px;
          info.fx_px = camera.fx_px;
          info.fy_px = camera.fy_px;
          info.cx_px = camera.cx_px;
          info.cy_px = camera.cy_px;
          info.distortion = camera.distortion;
          info.num_distortion = static_cast<int32_t>(camera.distortion.size());
          bus->publish(script.scene.channels.camera_info, info);
        }
        ++published;
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_progress > std::chrono::seconds(2)) {
      // Frames are stamped with their scheduled time: a camera drawing slower than its
      // frame rate publishes them late, and the pipeline's latency figures include that.
      const double behind_s = std::chrono::duration<double>(now - start).count() - t_s;
      std::fprintf(stderr, "arphys-synthetic-camera: t = %.1f / %.1f s, %lld frames%s\n", t_s, duration_s,
                   static_cast<long long>(frame_count),
                   !fast && behind_s > 2 * period_s
                       ? (", " + std::to_string(static_cast<int>(behind_s * 1000)) + " ms behind schedule").c_str()
                       : "");
      last_progress = now;
    }
  }
  std::fprintf(stderr, "arphys-synthetic-camera: %lld frames rendered, %lld published, %lld dropped by the drop rate\n",
               static_cast<long long>(frame_count), static_cast<long long>(published), static_cast<long long>(dropped));
  return 0;
}
