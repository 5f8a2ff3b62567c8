// arphys-simulator: the simulator process. Subscribes to tracked object poses and to
// commands, steps the world (CCD + Gauss least-constraint dynamics), publishes the
// world state every step and a 1 Hz heartbeat. See simulator/process/simulator_core.hpp
// for what it accepts and refuses.
//
// Clock: "messages" (default) steps up to the capture time of the newest tracking
// frame, so a replayed log (lcm-logplayer) gives the same world states on every run;
// "wall" steps with the wall clock (a scene without tracking, or a live demo).
// --max-lag-s bounds how far a simulator that cannot keep up falls behind (live runs; the
// launcher sets it): past it, the backlog of simulation time is given up, not stepped.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "simulator/app/live_simulator.hpp"
#include "simulator/dynamics/memory_policy.hpp"
#include "simulator/process/simulator_core.hpp"

using namespace arphys;

int main(int argc, char** argv) {
  CLI::App app{"arphys simulator process: tracked poses and commands in (LCM), world state out.\n"
               "Steps continuous collision detection and Gauss least-constraint dynamics."};
  std::string scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml";
  std::string clock = "messages", policy;
  sim::LiveOptions live;
  sim::CoreOptions& options = live.core;
  app.add_option("scene", scene_path, "scene YAML file")->capture_default_str();
  app.add_option("--lcm-url", live.lcm_url, "LCM URL (default: the scene's lcm.url)");
  app.add_option("--clock", clock, "messages: step to the newest tracking capture time (replay-deterministic); "
                                   "wall: step with the wall clock")
      ->check(CLI::IsMember({"messages", "wall"}))
      ->capture_default_str();
  app.add_option("--tracking-policy", policy, "override the scene's physics.tracking_policy")
      ->check(CLI::IsMember({"delay", "extrapolate"}));
  app.add_option("--catch-up-factor", options.driver_limits.catch_up_factor,
                 "a track re-acquired further on is caught up with at this many times the speed the object made "
                 "over the gap (at most 1.5 m/s): higher draws the real body where it is sooner and pushes what it "
                 "meets harder")
      ->check(CLI::Range(1.0, 100.0))
      ->capture_default_str();
  app.add_option("--duration", live.duration_s, "exit after this many wall-clock seconds (0: run until SIGINT)");
  app.add_option("--max-lag-s", live.max_lag_s,
                 "live runs: when the simulation falls more than this many seconds behind its clock (the newest "
                 "capture, or the wall), give the backlog up instead of stepping it, so the overlay stays current "
                 "and the virtual bodies run slow for a moment; counted in the heartbeat (dropped: steps, "
                 "dropped_time_s). 0: never (a replay is then the same on every run)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--threads", options.threads,
                 "worker threads of the step's collision queries (the world states are the same for any number)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--state-file", live.state_file,
                 "keep the last world state here (replaced 5 times a second); when the file exists at start, resume "
                 "its virtual bodies (after a crash or restart)");
  CLI11_PARSE(app, argc, argv);
  dynamics::keep_freed_memory_for_reuse();  // (memory_policy.hpp)

  config::SceneConfig scene;
  try {
    scene = config::load_scene(scene_path);
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "arphys-simulator: %s\n", e.what());
    return 2;
  }
  options.policy = sim::tracking_policy_from(policy.empty() ? scene.tracking_policy : policy);
  live.wall_clock = clock == "wall";
  return sim::run_live(scene, live);
}
