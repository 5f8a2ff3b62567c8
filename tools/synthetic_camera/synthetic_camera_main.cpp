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
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <thread>

#include "configs/loader/config_error.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "renderer/output/video_file.hpp"
#include "tools/synthetic_camera/scripted_camera.hpp"

namespace {

using namespace arphys;

struct Options {
  std::string script_path = config::default_config_dir() + "/synthetic/box_push.yaml";
  std::string url, video, folder;
  bool fast = false, no_lcm = false;
  int jpeg_quality = 90;
  int64_t max_frames = 0;
  double duration_s = 0;
};

// Every 2 s: where the run is, and how far behind its schedule (frames are stamped with
// their scheduled time: a camera drawing slower than its frame rate publishes them late,
// and the pipeline's latency figures include that).
void report_progress(const Options& o, double t_s, double period_s, int64_t frames, double elapsed_s) {
  const double behind_s = elapsed_s - t_s;
  const std::string behind = !o.fast && behind_s > 2 * period_s
                                 ? ", " + std::to_string(static_cast<int>(behind_s * 1000)) + " ms behind schedule"
                                 : "";
  std::fprintf(stderr, "arphys-synthetic-camera: t = %.1f / %.1f s, %lld frames%s\n", t_s, o.duration_s,
               static_cast<long long>(frames), behind.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "arphys synthetic camera: a scripted scene rendered with its markers, published on LCM with ground\n"
      "truth, and/or written to a video file or an image folder."};
  Options o;
  app.add_option("script", o.script_path, "camera script YAML (scene, camera pose, frame rate, effects, trajectories)")
      ->capture_default_str();
  app.add_option("--lcm-url", o.url, "LCM URL (default: the scene's lcm.url)");
  app.add_flag("--no-lcm", o.no_lcm, "publish nothing (files only)");
  app.add_flag("--fast", o.fast, "as fast as it renders, capture times still spaced by the frame period");
  app.add_option("--video", o.video, "also write the frames here (.avi: MJPG, .mp4: mp4v)");
  app.add_option("--folder", o.folder, "also write the frames here as frame_NNNNNN.png");
  app.add_option("--jpeg-quality", o.jpeg_quality,
                 "JPEG quality of published images; 0 publishes raw GRAY8 (mind the socket buffer: net.core.rmem_max)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  app.add_option("--duration", o.duration_s, "seconds to play (default: the script's duration_s)");
  app.add_option("--frames", o.max_frames, "stop after this many frames (0: no limit)");
  CLI11_PARSE(app, argc, argv);
  std::unique_ptr<synthetic::ScriptedCamera> camera;
  std::unique_ptr<msg::Bus> bus;
  try {
    camera = std::make_unique<synthetic::ScriptedCamera>(o.script_path);
    if (!o.no_lcm) bus = std::make_unique<msg::Bus>(o.url.empty() ? camera->script().scene.lcm_url : o.url);
    if (!o.folder.empty()) std::filesystem::create_directories(o.folder);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-synthetic-camera: %s\n", e.what());
    return 2;
  }
  const config::CameraScriptConfig& script = camera->script();
  if (o.duration_s <= 0) o.duration_s = script.duration_s;
  const double period_s = 1.0 / script.frame_rate_hz;
  cv::VideoWriter writer;
  camera->warm_up();  // before the clock starts, else every frame were published that much after its stamp
  const int64_t start_utime = msg::now_utime();
  const auto start = std::chrono::steady_clock::now();
  std::fprintf(stderr, "arphys-synthetic-camera: %s, %s, %.0f FPS for %.1f s%s\n", script.file.c_str(),
               camera->describe().c_str(), script.frame_rate_hz, o.duration_s, o.fast ? " (fast)" : "");
  int64_t published = 0, dropped = 0, frame_count = 0;
  auto last_progress = start;
  for (int64_t seq = 0;; ++seq) {
    const double t_s = seq * period_s;
    if (t_s > o.duration_s || (o.max_frames > 0 && seq >= o.max_frames)) break;
    if (!o.fast) std::this_thread::sleep_until(start + std::chrono::duration<double>(t_s));
    const int64_t capture_utime = start_utime + static_cast<int64_t>(std::llround(t_s * 1e6));
    synthetic::SceneAt at = camera->scene_at(t_s);
    const cv::Mat frame = camera->frame(at, seq);
    ++frame_count;
    try {
      if (!o.video.empty() && !writer.isOpened())
        writer = rendering::open_video_file(o.video, script.frame_rate_hz, frame.size(), false);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "arphys-synthetic-camera: %s\n", e.what());
      return 2;
    }
    if (writer.isOpened()) writer.write(frame);
    if (!o.folder.empty()) {
      char name[64];
      std::snprintf(name, sizeof name, "/frame_%06lld.png", static_cast<long long>(seq));
      cv::imwrite(o.folder + name, frame);
    }
    if (bus && camera->uniform() < script.effects.drop_rate) {
      ++dropped;
    } else if (bus) {
      if (!o.fast && script.effects.delay_ms > 0)
        std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(script.effects.delay_ms));
      synthetic::publish_frame(*bus, *camera, frame, at, capture_utime, seq, o.jpeg_quality);
      ++published;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_progress > std::chrono::seconds(2)) {
      report_progress(o, t_s, period_s, frame_count, std::chrono::duration<double>(now - start).count());
      last_progress = now;
    }
  }
  std::fprintf(stderr, "arphys-synthetic-camera: %lld frames rendered, %lld published, %lld dropped by the drop rate\n",
               static_cast<long long>(frame_count), static_cast<long long>(published), static_cast<long long>(dropped));
  return 0;
}
