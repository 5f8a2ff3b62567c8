// tracker: the tracker process. Camera frames in (V4L2, video file, image folder or an
// LCM image channel), fiducial markers detected (libapriltag or OpenCV ArUco, switchable
// at run time by a tracker_control_t message), object poses out on LCM, optionally as
// JSON lines or a human summary on stdout. See tracker/pipeline/tracker_pipeline.hpp.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/scene_config.hpp"
#include "tracker/app/live_tracker.hpp"
#include "tracker/detection/marker_detector.hpp"
#include "tracker/detection/marker_family.hpp"

namespace {

using namespace arphys;
using namespace arphys::tracking;

std::pair<std::string, std::string> split_param(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw std::invalid_argument("--param '" + text + "': expected NAME=VALUE (e.g. decimate=2)");
  }
  return {text.substr(0, eq), text.substr(eq + 1)};
}

// A folder holds independent pictures: apriltag searches them by candidate quads at full
// resolution (decimation 1's recall at a fifth of its cost, docs/tracker.md) unless the
// user chose the detector's parameters, or a family has no OpenCV dictionary to find quads.
void default_params_for_source(const std::string& source, DetectorSpec& spec) {
  if (spec.implementation != "apriltag" || !spec.params.empty() || !std::filesystem::is_directory(source)) return;
  for (const auto& family : spec.families)
    if (!has_aruco_dictionary(family)) return;
  spec.params.push_back({"candidate_search", "1"});
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys tracker: camera frames in, fiducial markers and 6-DoF object poses out (LCM, JSON).\n"
               "Poses are camera-from-marker and camera-from-object (metres, quaternions w x y z);\n"
               "corners in OpenCV's pixel convention (pixel centres at integers)."};
  RunOptions run;
  std::string camera_path, scene_path, impl = "apriltag", filter = "constant_velocity";
  std::vector<std::string> params, families;
  double marker_size_m = 0, predict_s = 0.1, max_fit_px = 2.0, marker_outlier_px = 3.0;
  app.add_option("--camera", camera_path, "camera calibration (OpenCV YAML); default: the scene's camera, else "
                                          "configs/cameras/synthetic_640x480.yaml");
  app.add_option("--source", run.source, "video file, image folder (name order), /dev/videoN, or lcm:CHANNEL "
                                     "(default: lcm:<the scene's camera image channel>)");
  app.add_option("--scene", scene_path, "scene YAML: the real objects and their markers");
  app.add_option("--marker-size", marker_size_m, "side of markers the scene does not declare, metres "
                                                 "(0: such markers get no pose)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--impl", impl, "detector implementation")->check(CLI::IsMember(detector_implementations()))
      ->capture_default_str();
  app.add_option("--family", families, "marker families to detect (default: the scene's, else tag36h11)");
  app.add_option("--param", params,
                 "detector parameter NAME=VALUE, repeatable. apriltag: decimate, sigma, "
                 "refine_edges, sharpening, threads, max_hamming, roi_tracking, coarse_decimate, "
                 "scan_tiles, coarse_every, candidate_search (default 1 for an image folder); aruco: "
                 "corner_refinement, subpix_window, aruco3, "
                 "min_marker_fraction, canonical_px, threshold_step, roi_tracking, coarse_decimate, "
                 "scan_tiles, coarse_every");
  app.add_option("--fps", run.fps, "frame rate of an image folder, for its capture times")->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--width", run.width, "V4L2: requested frame width, pixels");
  app.add_option("--height", run.height, "V4L2: requested frame height, pixels");
  app.add_option("--camera-fps", run.camera_fps, "V4L2: requested frame rate");
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
  app.add_flag("--json", run.json, "print one JSON line per frame on stdout; exit at the end of a file or folder");
  app.add_flag("--print", run.print, "print a short line per frame on stdout");
  app.add_option("--lcm-url", run.lcm_url, "LCM URL (default: the scene's lcm.url)");
  app.add_flag("--publish-images", run.publish_images, "republish the frames of a file or device source on the scene's "
                                                   "camera image channel (JPEG), for the renderer");
  app.add_flag("--pace", run.pace, "play a file or folder source at its own frame rate instead of as fast as possible");
  app.add_flag("--no-lcm", run.no_lcm, "do not publish on LCM (file and folder sources only)");
  app.add_option("--name", run.name, "process name, matched by tracker_control_t.target")->capture_default_str();
  app.add_option("--duration", run.duration_s, "exit after this many seconds (0: until the source ends or SIGINT)");
  app.add_option("--max-frames", run.max_frames, "exit after this many frames (0: no limit)");
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
    default_params_for_source(run.source, spec);
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
  if (run.source.empty()) run.source = "lcm:" + scene.channels.camera_image;
  run.camera_path = camera_path;
  return run_tracker(scene, camera_config, *pipeline, run);
}
