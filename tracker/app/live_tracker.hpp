#pragma once
// The tracker process around its pipeline: frames from a source (file, folder, device or an
// LCM image channel), each tracked, poses and detections out on LCM and as JSON or summary
// lines on stdout, detector switches by tracker_control_t, a heartbeat a second.
#include <memory>
#include <string>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/scene_config.hpp"
#include "tracker/pipeline/tracker_pipeline.hpp"

namespace arphys::tracking {

struct RunOptions {
  std::string name = "tracker";  // matched by tracker_control_t.target
  std::string camera_path;       // for messages
  std::string source;            // video file, image folder, /dev/videoN or lcm:CHANNEL
  std::string lcm_url;           // empty: the scene's
  double fps = 30;               // an image folder's frame rate
  int width = 0, height = 0;     // V4L2 request (0: the device's)
  double camera_fps = 0;
  bool json = false, print = false, no_lcm = false, publish_images = false, pace = false;
  double duration_s = 0;  // 0: until the source ends or a signal
  int64_t max_frames = 0;
};

// Runs until the source ends, the duration, the frame limit or a signal. Returns the exit
// code: 2 when the bus or the source cannot be opened, or the frames are not the size the
// camera is calibrated for (the reason is printed).
int run_tracker(const config::SceneConfig& scene, const config::CameraConfig& camera, TrackerPipeline& pipeline,
                const RunOptions& options);

}  // namespace arphys::tracking
