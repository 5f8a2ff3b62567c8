#pragma once
// The simulator process on LCM: tracked poses and commands in, the world state out every
// step, a heartbeat a second, the last state kept in a file to resume from. What it
// accepts and refuses is SimulatorCore's (simulator/process/simulator_core.hpp).
#include <string>

#include "configs/loader/scene_config.hpp"
#include "simulator/process/simulator_core.hpp"

namespace arphys::sim {

struct LiveOptions {
  std::string lcm_url;      // empty: the scene's
  bool wall_clock = false;  // step with the wall clock, not to the newest capture time
  double duration_s = 0;    // 0: until SIGINT or SIGTERM
  double max_lag_s = 0;     // give up the backlog past this lag (0: never)
  std::string state_file;   // keep the last world state here and resume from it
  CoreOptions core;
};

// Runs until the duration or a signal. Returns the exit code (2: the core or the bus
// cannot be set up; the reason is printed).
int run_live(const config::SceneConfig& scene, const LiveOptions& options);

}  // namespace arphys::sim
