#include "tools/launch/launch_options.hpp"

namespace arphys::launch {

bool LaunchOptions::wanted(const std::string& name) const {
  return only.empty() || ("," + only + ",").find("," + name + ",") != std::string::npos;
}

void add_launch_options(CLI::App& app, LaunchOptions& o) {
  app.add_option("scene", o.scene_path, "scene YAML")->capture_default_str();
  app.add_option("--camera", o.camera, "synthetic (the scene's camera script), /dev/videoN, or a video file")
      ->capture_default_str();
  app.add_option("--script", o.script_path, "camera script for --camera synthetic (default: the scene's, "
                                            "configs/synthetic/box_push.yaml or spoon_approach.yaml)");
  app.add_option("--tracker", o.tracker_impl, "tracker implementation")
      ->check(CLI::IsMember({"apriltag", "aruco"}))
      ->capture_default_str();
  app.add_option("--tracker-filter", o.tracker_filter,
                 "the tracker's pose filter (tracker --filter): constant_velocity keeps a noisy tracked box from "
                 "pushing faster than it moves")
      ->check(CLI::IsMember({"none", "one_euro", "constant_velocity"}))
      ->capture_default_str();
  app.add_option("--duration", o.duration_s,
                 "seconds to run (the synthetic camera plays this much of its script; a camera drawing slower than "
                 "real time is waited for, up to 20 s more)")
      ->capture_default_str();
  app.add_option("--out", o.out_dir, "write overlay.avi, latency.json, process logs (and run.lcmlog) here");
  app.add_flag("--restart", o.restart, "restart a process that dies (reported, counted) instead of stopping the run");
  app.add_flag("--record", o.record, "record all traffic with lcm-logger to OUT/run.lcmlog");
  app.add_option("--replay", o.replay_log,
                 "play this lcm-logger file (arphys-replay) instead of a camera, into fresh processes; the run ends "
                 "with the log (give a --duration at least its length)")
      ->check(CLI::ExistingFile);
  app.add_option("--replay-what", o.replay_what,
                 "frames: the recorded camera frames, re-tracked; poses: the recorded tracked poses, into the "
                 "simulator alone")
      ->check(CLI::IsMember({"frames", "poses"}))
      ->capture_default_str();
  app.add_option("--only", o.only,
                 "comma-separated subset to start: camera,tracker,simulator,renderer,view (other "
                 "machines run the rest)");
  app.add_option_function<int>(
         "--view", [&o](const int& port) { o.view_port = port; },
         "serve the run to a browser and to Foxglove or Lichtblick (arphys-view) on this port, and publish the "
         "overlay for it (with --replay, the page drives the replay)")
      ->expected(0, 1)
      ->default_str("8765")
      ->check(CLI::Range(1, 65535));
  app.add_flag("--view-allow-spawn", o.view_allow_spawn,
               "let the view's clients (the page's spawn button) spawn the scene's models (arphys-view --allow-spawn)");
  app.add_option("--spawn-every", o.spawn_every_s,
                 "spawn the scene's first dynamic virtual model every S seconds, thrown onto the table (0: none)")
      ->capture_default_str();
  app.add_option("--lcm-url", o.lcm_url, "LCM URL for every process (default: the scene's)");
  app.add_option("--tracking-policy", o.tracking_policy, "override the scene's tracking policy in the simulator")
      ->check(CLI::IsMember({"delay", "extrapolate"}));
  app.add_option("--catch-up-factor", o.catch_up_factor,
                 "the simulator's --catch-up-factor: a re-acquired track is caught up with at this many times the "
                 "object's own speed over the gap (default: the simulator's, 2)")
      ->check(CLI::Range(1.0, 100.0));
  app.add_option("--renderer-wait-ms", o.renderer_wait_ms,
                 "the renderer holds each frame up to this long for the world state computed from it (renderer "
                 "--wait-ms): the overlay shows the frame's own world, later")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--sim-max-lag-s", o.sim_max_lag_s,
                 "a simulator falling further behind the camera than this gives the backlog up (its virtual bodies "
                 "run slow for a moment) instead of lagging ever more (arphys-simulator --max-lag-s; 0: never)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--sim-threads", o.sim_threads,
                 "worker threads of the simulator's collision queries (arphys-simulator --threads; the world states "
                 "are the same for any number)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--receive-loss", o.receive_loss,
                 "fault injection: every started process drops this fraction of the messages it receives, at random "
                 "(ARPHYS_FAULT_RECEIVE_LOSS)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--build", o.build_dir, "build directory holding the executables")->capture_default_str();
}

}  // namespace arphys::launch
