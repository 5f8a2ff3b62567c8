#pragma once
// arphys-launch's command line: what to run, how, and where its results go.
#include <string>

#include <CLI/CLI.hpp>

namespace arphys::launch {

struct LaunchOptions {
  std::string scene_path;
  std::string camera = "synthetic";  // synthetic, /dev/videoN or a video file
  std::string script_path;           // the synthetic camera's script (default: the scene's)
  std::string tracker_impl = "apriltag";
  std::string tracker_filter = "constant_velocity";
  std::string out_dir;
  std::string only;  // comma-separated subset of camera,tracker,simulator,renderer,view
  std::string lcm_url;
  std::string tracking_policy;
  std::string build_dir;
  std::string replay_log;              // an lcm-logger file played instead of a camera (arphys-replay)
  std::string replay_what = "frames";  // frames (into tracker, simulator, renderer) or poses (into the simulator)
  double duration_s = 20;
  double spawn_every_s = 1.0;
  double renderer_wait_ms = 0;
  double sim_max_lag_s = 0.1;
  double catch_up_factor = 0;  // 0: the simulator's own default
  double receive_loss = 0;
  int sim_threads = 1;
  int view_port = -1;  // arphys-view on this port (--view [PORT]); -1: none
  bool record = false;
  bool view_allow_spawn = false;  // arphys-view --allow-spawn: the page's spawn button
  bool restart = false;

  // Whether the process `name` is started here (--only).
  bool wanted(const std::string& name) const;
};

// Declares every option on `app`, with its default taken from `options`.
void add_launch_options(CLI::App& app, LaunchOptions& options);

}  // namespace arphys::launch
