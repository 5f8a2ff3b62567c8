#include "tools/launch/process_commands.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <sstream>

namespace arphys::launch {

std::string default_script_for(const config::SceneConfig& scene) {
  const std::string dir = config::default_config_dir() + "/synthetic/";
  if (scene.name == "bunny_box_table") return dir + "box_push.yaml";
  if (scene.name == "spoon_teacup") return dir + "spoon_approach.yaml";
  return "";
}

bool ends_by_itself(const std::string& name, const LaunchOptions& options) {
  const bool file_source = options.camera != "synthetic" && options.camera.rfind("/dev/video", 0) != 0;
  return name == "camera" || (name == "tracker" && file_source);
}

namespace {

constexpr double kReplayRendererWaitMs = 100;

std::string url_of(const LaunchOptions& o, const config::SceneConfig& scene) {
  return o.lcm_url.empty() ? scene.lcm_url : o.lcm_url;
}

// Children outlive the run: the launcher stops them, so any earlier exit is a death.
std::string lifetime_s(const LaunchOptions& o) { return std::to_string(o.duration_s + 30); }

std::vector<std::string> simulator_args(const LaunchOptions& o, const config::SceneConfig& scene,
                                        const std::string& state_file) {
  std::vector<std::string> args{o.build_dir + "/simulator/app/arphys-simulator", scene.file, "--lcm-url", url_of(o, scene),
                                "--duration", lifetime_s(o), "--state-file", state_file};
  if (!o.tracking_policy.empty()) args.insert(args.end(), {"--tracking-policy", o.tracking_policy});
  if (o.catch_up_factor > 0) args.insert(args.end(), {"--catch-up-factor", std::to_string(o.catch_up_factor)});
  if (o.sim_max_lag_s > 0) args.insert(args.end(), {"--max-lag-s", std::to_string(o.sim_max_lag_s)});
  if (o.sim_threads > 1) args.insert(args.end(), {"--threads", std::to_string(o.sim_threads)});
  // A replay steps to the recorded capture times: the same world states on every replay.
  if (!o.replay_log.empty()) args.insert(args.end(), {"--clock", "messages"});
  return args;
}

// The replay in the camera's place: the recorded frames (with what the camera published
// beside them) or only the tracked poses.
std::vector<std::string> replay_args(const LaunchOptions& o, const config::SceneConfig& scene) {
  const auto& ch = scene.channels;
  const std::string channels =
      o.replay_what == "poses" ? ch.object_poses : ch.camera_image + "|" + ch.camera_info + "|" + ch.ground_truth;
  return {o.build_dir + "/tools/replay/arphys-replay",
          o.replay_log,
          "--lcm-url",
          url_of(o, scene),
          "--channels",
          channels,
          "--frame-channel",
          o.replay_what == "poses" ? ch.object_poses : ch.camera_image};
}

std::vector<std::string> renderer_args(const LaunchOptions& o, const config::SceneConfig& scene,
                                       const config::CameraScriptConfig* script) {
  std::vector<std::string> args{o.build_dir + "/renderer/app/renderer", "--scene", scene.file, "--lcm-url",
                                url_of(o, scene), "--duration", lifetime_s(o)};
  // A replay is not live: each frame waits for the world state computed from it (one frame
  // behind, the replayed box was drawn 3.5 px off its image; its own, 2.3 px).
  const double wait_ms =
      o.replay_log.empty() ? o.renderer_wait_ms : std::max(o.renderer_wait_ms, kReplayRendererWaitMs);
  if (wait_ms > 0) args.insert(args.end(), {"--wait-ms", std::to_string(wait_ms)});
  if (o.view_port > 0) args.push_back("--overlay-lcm");  // the view's /overlay
  if (!o.out_dir.empty()) {
    args.insert(args.end(), {"--video", o.out_dir + "/overlay.avi", "--png-dir", o.out_dir + "/snapshots", "--png-every", "90"});
  }
  if (script) {  // the synthetic camera's pose, which no marker gives the renderer
    const auto t = script->X_WC.translation();
    const Eigen::Quaterniond q(script->X_WC.linear());
    std::ostringstream pose;
    pose << t.x() << " " << t.y() << " " << t.z() << " " << q.w() << " " << q.x() << " " << q.y() << " " << q.z();
    args.insert(args.end(), {"--camera-pose", pose.str()});
  }
  return args;
}

std::vector<std::string> tracker_args(const LaunchOptions& o, const config::SceneConfig& scene) {
  std::vector<std::string> args{o.build_dir + "/tracker/app/tracker", "--scene", scene.file, "--lcm-url", url_of(o, scene),
                                "--impl", o.tracker_impl, "--filter", o.tracker_filter, "--duration", lifetime_s(o)};
  if (o.camera != "synthetic") args.insert(args.end(), {"--source", o.camera, "--publish-images", "--pace"});
  return args;
}

}  // namespace

std::vector<ProcessCommand> process_commands(const LaunchOptions& o, const config::SceneConfig& scene,
                                             const config::CameraScriptConfig* script, const std::string& state_file) {
  std::vector<ProcessCommand> commands;
  if (o.record && !o.out_dir.empty()) {
    commands.push_back({"recorder", {"lcm-logger", "--lcm-url=" + url_of(o, scene), "--force", o.out_dir + "/run.lcmlog"}});
  }
  if (o.wanted("simulator")) commands.push_back({"simulator", simulator_args(o, scene, state_file)});
  if (o.wanted("renderer")) commands.push_back({"renderer", renderer_args(o, scene, script)});
  if (o.view_port > 0 && o.wanted("view")) {
    commands.push_back({"view",
                        {o.build_dir + "/tools/view/arphys-view", scene.file, "--lcm-url", url_of(o, scene), "--port",
                         std::to_string(o.view_port)}});
    if (o.view_allow_spawn) commands.back().args.push_back("--allow-spawn");
    if (!o.replay_log.empty()) commands.back().args.push_back("--allow-replay-control");  // the page drives the replay
  }
  const bool replaying = !o.replay_log.empty();
  if (o.wanted("tracker") && !(replaying && o.replay_what == "poses"))
    commands.push_back({"tracker", tracker_args(o, scene)});
  if (replaying && o.wanted("camera")) {
    commands.push_back({"camera", replay_args(o, scene)});
  } else if (script && o.wanted("camera")) {
    commands.push_back({"camera", {o.build_dir + "/tools/synthetic_camera/arphys-synthetic-camera", script->file,
                                   "--lcm-url", url_of(o, scene), "--duration", std::to_string(o.duration_s)}});
  }
  return commands;
}

}  // namespace arphys::launch
