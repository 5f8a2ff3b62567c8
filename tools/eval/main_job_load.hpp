#pragma once
// The main job's simulator load without LCM and without the other processes: the
// synthetic camera's script (configs/synthetic/box_push.yaml) moves the tracked box and
// its exact poses reach the simulator core at the script's frame rate, as a perfect
// tracker's would; a bunny is spawned every second as arphys-launch spawns them
// (launch::MainJobThrows; seed 7 is the launcher's). Each frame the core steps up to the
// frame's capture time, timed.
//
// The pile the box shoves is chaotic: a change in the last bit of any contact sends the
// bunnies elsewhere (one falls off the table, or one more lies in front of the box), and
// one run's cost moves by a third with it. Compare code by the mean over several seeds,
// not by one run.
#include <vector>

#include "configs/loader/camera_script.hpp"

namespace arphys::eval {

struct LoadSecond {
  int second = 0;             // [second, second + 1) of simulation time
  double ms_per_step = 0;     // CPU (wall, one thread) per simulation step in that second
  int steps = 0;
  double max_frame_ms = 0;    // the slowest frame's steps: what makes the live job give up time
  int virtual_bodies = 0;     // at the end of the second
  int bodies_left_world = 0;  // fallen off the table so far (and removed)
};

// Throws std::invalid_argument unless duration_s > 0, the script moves an object called
// "box" (the simulator refuses, and counts, poses of one that is not tracked) and its
// scene has a virtual dynamic model to spawn.
std::vector<LoadSecond> run_main_job_load(const config::CameraScriptConfig& script, unsigned seed, double duration_s);

}  // namespace arphys::eval
