// tracker: the tracker process. Camera frames in (V4L2, video file, image folder or an
// LCM image channel), fiducial markers detected (libapriltag or OpenCV ArUco, switchable
// at run time by a tracker_control_t message), object poses out on LCM, optionally as
// JSON lines or a human summary on stdout. See tracker/pipeline/tracker_pipeline.hpp.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <thread>

#include "arphys/image_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "tracker/app/lcm_image_source.hpp"
#include "tracker/app/tracker_output.hpp"
#include "tracker/detection/marker_detector.hpp"

namespace {

using namespace arphys;
using namespace arphys::tracking;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

std::pair<std::string, std::string> split_param(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw std::invalid_argument("--param '" + text + "': expected NAME=VALUE (e.g. decimate=2)");
  }
  return {text.substr(0, eq), text.substr(eq + 1)};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys tracker: camera frames in, fiducial markers and 6-DoF object poses out (LCM, JSON).\n"
               "Poses are camera-from-marker and camera-from-object (metres, quaternions w x y z);\n"
               "corners in OpenCV's pixel convention (pixel centres at integers)."};
  std::string camera_path, source, scene_path, impl = "apriltag", url, name = "tracker", filter = "constant_velocity";
  std::vector<std::string> params, families;
  double marker_size_m = 0, fps = 30, camera_fps = 0, predict_s = 0.1, duration_s = 0, max_fit_px = 2.0,
         marker_outlier_px = 3.0;
  int width = 0, height = 0;
  int64_t max_frames = 0;
  bool json = false, print = false, no_lcm = false, publish_images = false, pace = false;
  app.add_option("--camera", camera_path, "camera calibration (OpenCV YAML); default: the scene's camera, else "
                                          "configs/cameras/synthetic_640x480.yaml");
  app.add_option("--source", source, "video file, image folder (name order), /dev/videoN, or lcm:CHANNEL "
                                     "(default: lcm:<the scene's camera image channel>)");
  app.add_option("--scene", scene_path, "scene YAML: the real objects and their markers");
  app.add_option("--marker-size", marker_size_m, "side of markers the scene does not declare, metres "
                                                 "(0: such markers get no pose)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--impl", impl, "detector implementation")->check(CLI::IsMember(detector_implementations()))
      ->capture_default_str();
  app.add_option("--family", families, "marker families to detect (default: the scene's, else tag36h11)");
  app.add_option("--param", params, "detector parameter NAME=VALUE, repeatable. apriltag: decimate, sigma, "
                                    "refine_edges, sharpening, threads, max_hamming, roi_tracking, coarse_decimate, "
                                    "scan_tiles; aruco: corner_refinement, subpix_window, aruco3, min_marker_fraction, "
                                    "canonical_px, threshold_step, roi_tracking, coarse_decimate, scan_tiles");
  app.add_option("--fps", fps, "frame rate of an image folder, for its capture times")->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--width", width, "V4L2: requested frame width, pixels");
  app.add_option("--height", height, "V4L2: requested frame height, pixels");
  app.add_option("--camera-fps", camera_fps, "V4L2: requested frame rate");
  app.add_option("--predict-s", predict_s, "an object not seen is PREDICTED for this long, then LOST, seconds")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--max-fit-px", max_fit_px, "an object whose markers miss their fit by more than this RMS is not "
                                            "TRACKED (a wrong layout), pixels")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--marker-outlier-px", marker_outlier_px, "a marker of a multi-marker object that misses the others' "
                                                          "fit by more than this RMS is left out and named, pixels")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--filter", filter, "pose filter on object and camera poses: one_euro steadies a still marker, "
                                     "constant_velocity (a Kalman filter) smooths a moving one for physics (the default, as in arphys-launch), "
                                     "none publishes the raw fits")
      ->check(CLI::IsMember({"none", "one_euro", "constant_velocity"}))
      ->capture_default_str();
  app.add_flag("--json", json, "print one JSON line per frame on stdout; exit at the end of a file or folder");
  app.add_flag("--print", print, "print a short line per frame on stdout");
  app.add_option("--lcm-url", url, "LCM URL (default: the scene's lcm.url)");
  app.add_flag("--publish-images", publish_images, "republish the frames of a file or device source on the scene's "
                                                   "camera image channel (JPEG), for the renderer");
  app.add_flag("--pace", pace, "play a file or folder source at its own frame rate instead of as fast as possible");
  app.add_flag("--no-lcm", no_lcm, "do not publish on LCM (file and folder sources only)");
  app.add_option("--name", name, "process name, matched by tracker_control_t.target")->capture_default_str();
  app.add_option("--duration", duration_s, "exit after this many seconds (0: until the source ends or SIGINT)");
  app.add_option("--max-frames", max_frames, "exit after this many frames (0: no limit)");
  CLI11_PARSE(app, argc, argv);

  config::SceneConfig scene;
  config::CameraConfig camera_config;
  std::unique_ptr<TrackerPipeline> pipeline;
  try {
    if (!scene_path.empty()) scene = config::load_scene(scene_path);
    if (camera_path.empty()) {
      camera_path = scene.camera_file.empty() ? config::default_config_dir() + "/cameras/synthetic_640x480.yaml"
                                              : scene.camera_file;
    }
    camera_config = config::load_camera(camera_path);
    TrackerModel model = TrackerModel::from_scene(scene, marker_size_m);
    DetectorSpec spec;
    spec.implementation = impl;
    spec.families = families.empty() ? families_of(model) : families;
    for (const auto& p : params) spec.params.push_back(split_param(p));
    TrackerOptions options;
    options.predict_s = predict_s;
    options.max_fit_rms_px = max_fit_px;
    options.consensus.marker_outlier_px = marker_outlier_px;
    options.filter.kind = pose_filter_kind_from(filter);
    pipeline = std::make_unique<TrackerPipeline>(
        make_detector(spec), ObjectTracker(std::move(model), CameraModel::from_config(camera_config), options));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tracker: %s\n", e.what());
    return 2;
  }
  if (source.empty()) source = "lcm:" + scene.channels.camera_image;

  std::unique_ptr<msg::Bus> bus;
  const bool lcm_source = source.rfind("lcm:", 0) == 0;
  if (!no_lcm || lcm_source) {
    try {
      bus = std::make_unique<msg::Bus>(url.empty() ? scene.lcm_url : url);
    } catch (const std::exception& e) {
      if (lcm_source || !json) {
        std::fprintf(stderr, "tracker: %s\n", e.what());
        return 2;
      }
      std::fprintf(stderr, "tracker: LCM unavailable, JSON only (%s)\n", e.what());
    }
  }
  std::unique_ptr<FrameSource> frames;
  LcmImageSource* lcm_frames = nullptr;
  try {
    if (lcm_source) {
      auto s = std::make_unique<LcmImageSource>(*bus, source.substr(4));
      lcm_frames = s.get();
      frames = std::move(s);
    } else {
      frames = open_frame_source(source, fps, width, height, camera_fps);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tracker: %s\n", e.what());
    return 2;
  }

  if (bus) {
    bus->subscribe<arphys::tracker_control_t>(
        scene.channels.tracker_control,
        [&](const arphys::tracker_control_t& m, const lcm::ReceiveBuffer&, const std::string&) {
          if (!m.target.empty() && m.target != name) return;
          try {
            if (m.param_names.size() != m.param_values.size()) throw std::invalid_argument("names and values differ in count");
            if (!m.implementation.empty()) {
              DetectorSpec spec;
              spec.implementation = m.implementation;
              for (size_t i = 0; i < m.param_names.size(); ++i) spec.params.emplace_back(m.param_names[i], m.param_values[i]);
              pipeline->switch_detector(spec);
            } else {
              for (size_t i = 0; i < m.param_names.size(); ++i) {
                pipeline->set_detector_param(m.param_names[i], m.param_values[i]);
              }
            }
            std::fprintf(stderr, "tracker: detector now %s\n", pipeline->detector().describe().c_str());
          } catch (const std::exception& e) {
            pipeline->count_rejected_control();
            std::fprintf(stderr, "tracker: control refused, detector unchanged: %s\n", e.what());
            throw;  // counted by the bus as a rejected message too
          }
        });
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  const std::string camera_id = camera_config.camera_id.empty() ? "camera" : camera_config.camera_id;
  std::fprintf(stderr, "tracker: source %s, camera %s (%dx%d), %zu objects, detector %s%s\n",
               frames->describe().c_str(), camera_path.c_str(), camera_config.width_px, camera_config.height_px,
               pipeline->tracker().model().objects.size(), pipeline->detector().describe().c_str(),
               bus ? (", LCM " + bus->url()).c_str() : "");
  const auto start = std::chrono::steady_clock::now();
  auto last_status = start;
  int64_t frame_index = 0, published = 0, frames_since_status = 0;
  double detect_ms_since_status = 0;
  bool first_frame = true;
  std::optional<int64_t> paced_first_utime;  // --pace: the first frame's time and when it was shown
  std::chrono::steady_clock::time_point paced_start;
  while (!g_stop) {
    const auto now = std::chrono::steady_clock::now();
    if (duration_s > 0 && std::chrono::duration<double>(now - start).count() > duration_s) break;
    if (max_frames > 0 && frame_index >= max_frames) break;
    if (bus && !lcm_source) bus->handle_pending();
    std::optional<Frame> frame = frames->next(50);
    if (!frame && frames->finished()) break;
    if (frame && pace && !lcm_source) {
      // Frame times of a file count from its first frame: wait for each one's turn.
      if (!paced_first_utime) {
        paced_first_utime = frame->capture_utime;
        paced_start = std::chrono::steady_clock::now();
      }
      std::this_thread::sleep_until(paced_start + std::chrono::microseconds(frame->capture_utime - *paced_first_utime));
    }
    if (frame) {
      if (first_frame && !lcm_source &&
          (frame->image.cols != camera_config.width_px || frame->image.rows != camera_config.height_px)) {
        std::fprintf(stderr, "tracker: camera file %s is calibrated for %dx%d but %s gives %dx%d frames; refusing to "
                     "track with the wrong calibration\n",
                     camera_path.c_str(), camera_config.width_px, camera_config.height_px, frames->describe().c_str(),
                     frame->image.cols, frame->image.rows);
        return 2;
      }
      first_frame = false;
      if (bus && publish_images && !lcm_source) {
        bus->publish(scene.channels.camera_image,
                     msg::encode_image_message(frame->image, frame->capture_utime, frame->seq, camera_id));
      }
      const auto report = pipeline->process(*frame, frames->frames_independent());
      if (report) {
        if (json) std::cout << frame_json(*report, frame_index).dump() << std::endl;
        if (print) std::cout << frame_summary(*report) << std::endl;
        if (bus) {
          bus->publish(scene.channels.marker_detections, detections_message(*report, camera_id));
          bus->publish(scene.channels.object_poses, poses_message(*report, camera_id));
          published += 2;
        }
        ++frames_since_status;
        detect_ms_since_status += report->detect_ms;
      }
      ++frame_index;
    }
    const auto after = std::chrono::steady_clock::now();
    if (bus && after - last_status >= std::chrono::seconds(1)) {
      const double window_s = std::chrono::duration<double>(after - last_status).count();
      const auto& c = pipeline->counters();
      arphys::process_status_t status =
          msg::heartbeat(name, pipeline->detector().describe(), std::chrono::duration<double>(after - start).count(), *bus);
      status.rate_hz = frames_since_status / window_s;
      status.stage_duration_ms = frames_since_status ? detect_ms_since_status / frames_since_status : 0.0;
      status.published = published;
      status.dropped = lcm_frames ? lcm_frames->dropped_frames() : 0;
      status.decode_errors += frames->skipped_frames();
      const int64_t out_of_order = lcm_frames ? lcm_frames->out_of_order_frames() : 0;
      status.rejected += c.wrong_size + c.wrong_format + out_of_order;
      status.state = frames_since_status ? "tracking" : "waiting for frames";
      const std::vector<std::pair<std::string, double>> figures = {
          {"frames", static_cast<double>(c.frames)},
          {"wrong_size_frames", static_cast<double>(c.wrong_size)},
          {"wrong_format_frames", static_cast<double>(c.wrong_format)},
          {"duplicate_or_out_of_order_frames", static_cast<double>(out_of_order)},
          {"unknown_markers", static_cast<double>(c.unknown_markers)},
          {"rejected_poses", static_cast<double>(c.rejected_poses)},
          {"rejected_markers", static_cast<double>(c.rejected_markers)},
          {"poor_fits", static_cast<double>(c.poor_fits)},
          {"detector_switches", static_cast<double>(c.detector_switches)},
          {"rejected_controls", static_cast<double>(c.rejected_controls)}};
      for (const auto& [n, v] : figures) msg::add_figure(status, n, v);
      bus->publish(scene.channels.process_status, status);
      last_status = after;
      frames_since_status = 0;
      detect_ms_since_status = 0;
    }
  }
  const auto& c = pipeline->counters();
  std::fprintf(stderr, "tracker: %lld frames, %lld skipped (size %lld, format %lld, unreadable %lld), %lld unknown "
               "markers ignored, %lld outlier poses dropped by the filter, %lld markers left out of fits, %lld fits above "
               "--max-fit-px, %lld detector switches, %lld controls refused\n",
               static_cast<long long>(c.frames), static_cast<long long>(c.wrong_size + c.wrong_format + frames->skipped_frames()),
               static_cast<long long>(c.wrong_size), static_cast<long long>(c.wrong_format),
               static_cast<long long>(frames->skipped_frames()), static_cast<long long>(c.unknown_markers),
               static_cast<long long>(c.rejected_poses), static_cast<long long>(c.rejected_markers),
               static_cast<long long>(c.poor_fits), static_cast<long long>(c.detector_switches), static_cast<long long>(c.rejected_controls));
  return 0;
}
