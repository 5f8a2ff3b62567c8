#include "tools/eval/main_job_load.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "simulator/dynamics/kinematic_trajectory.hpp"
#include "simulator/process/simulator_core.hpp"
#include "tools/launch/main_job_throws.hpp"

namespace arphys::eval {

std::vector<LoadSecond> run_main_job_load(const config::CameraScriptConfig& script, unsigned seed, double duration_s) {
  if (!(duration_s > 0)) throw std::invalid_argument("main-job-load: duration_s must be > 0, got " + std::to_string(duration_s));
  const auto keys = script.trajectories.find("box");
  if (keys == script.trajectories.end())
    throw std::invalid_argument("main-job-load: " + script.file + " moves no object called 'box'");
  dynamics::KinematicTrajectory box;
  for (const auto& key : keys->second) box.add(key.t_s, key.X_WO);
  const config::ObjectConfig* model = launch::thrown_model(script.scene);
  if (!model) throw std::invalid_argument("main-job-load: " + script.scene.file + " has no virtual dynamic model to spawn");

  sim::SimulatorCore core(script.scene, sim::CoreOptions{});
  launch::MainJobThrows throws(seed);  // what arphys-launch throws in, one a second
  const int64_t start_utime = 1'700'000'000'000'000;
  const double period_s = 1.0 / script.frame_rate_hz;
  std::vector<LoadSecond> seconds;
  LoadSecond current;
  double current_ms = 0;
  int64_t spawned = 0;
  for (int64_t seq = 0;; ++seq) {
    const double t_s = static_cast<double>(seq) * period_s;
    if (t_s > duration_s) break;
    sim::TrackingFrame frame;
    frame.capture_utime = start_utime + static_cast<int64_t>(std::llround(t_s * 1e6));
    frame.seq = seq;
    frame.objects.push_back({"box", false, true, box.pose_at(t_s)});
    core.on_tracking(frame);
    if (t_s >= static_cast<double>(spawned + 1)) {
      sim::SpawnRequest spawn;
      spawn.sender = "main-job-load";
      spawn.seq = ++spawned;
      spawn.model = model->id;
      const launch::Throw thrown = throws.next();
      spawn.X_WB = thrown.X_WB;
      spawn.v_WB_m_s = thrown.v_WB_m_s;
      core.on_command(spawn);  // (refused past the model's max_instances, as in the job)
    }
    const auto before = std::chrono::steady_clock::now();
    const int steps = core.advance_to(core.sim_time_of(frame.capture_utime));
    const double frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - before).count();
    current_ms += frame_ms;
    current.max_frame_ms = std::max(current.max_frame_ms, frame_ms);
    current.steps += steps;
    const int second = static_cast<int>(std::floor(core.sim_time_s() + 1e-9));
    if (second > current.second) {
      current.ms_per_step = current.steps > 0 ? current_ms / current.steps : 0.0;
      current.virtual_bodies = 0;
      for (const auto& body : core.world().body_copies()) current.virtual_bodies += body.is_dynamic();
      current.bodies_left_world = static_cast<int>(core.bodies_left_world());
      seconds.push_back(current);
      current = LoadSecond{};
      current.second = second;
      current_ms = 0;
    }
  }
  return seconds;
}

}  // namespace arphys::eval
