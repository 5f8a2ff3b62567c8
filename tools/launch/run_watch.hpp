#pragma once
// What arphys-launch watches on the bus while a run goes on: latency per stage from the
// messages themselves, the overlay's registration against the synthetic camera's ground
// truth, each process's heartbeat and resident memory. It prints the status line and
// writes the run's report.
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "arphys/process_status_t.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "tools/launch/latency_report.hpp"
#include "tools/launch/launch_options.hpp"
#include "tools/launch/registration_report.hpp"

namespace arphys::launch {

// Resident memory of each process over the run, from its heartbeats: the figure a leak
// shows in. The baseline is taken once the process has run warm_up_s (caches, the first
// frames and meshes are loaded by then); a restarted process starts a new one.
class MemoryWatch {
 public:
  void on_heartbeat(const arphys::process_status_t& status);
  nlohmann::json to_json() const;
  void print() const;  // growth after warm-up per process, on stderr

 private:
  static constexpr double kWarmUpS = 10;
  struct Process {
    int32_t pid = 0;
    double baseline_mb = -1, baseline_uptime_s = 0, last_mb = 0, last_uptime_s = 0, max_mb = 0;
  };
  std::map<std::string, Process> processes_;
};

class RunWatch {
 public:
  // Subscribes to the scene's channels on `bus`; measures registration when the scene has
  // a camera and `synthetic` (ground truth is published), else says why not on stderr.
  RunWatch(msg::Bus& bus, const config::SceneConfig& scene, bool synthetic);

  // One line: each process's rate, stage time, given-up steps, drops and rejections.
  std::string status_line(double elapsed_s) const;
  int64_t frame_messages() const { return latency_.frame_messages(); }
  // latency.json: stages, frames, memory, registration, the simulator's drop, and the run's
  // settings; restarts by process; drain_ended_by "settled" or "drain_limit" (how the run
  // ended after the camera's last frame; else null) after drain_s.
  nlohmann::json report(const LaunchOptions& options, const config::SceneConfig& scene,
                        const std::map<std::string, int>& restarts, const std::string& drain_ended_by,
                        double drain_s) const;
  // The tables and lines a user reads at the end (stdout; memory on stderr).
  void print(const nlohmann::json& report) const;
  void write_samples_csv(const std::string& path) const { latency_.write_samples_csv(path); }

 private:
  // The simulation time the simulator's last heartbeat says it gave up (--max-lag-s).
  std::optional<double> simulator_dropped_time_s() const;

  tools::LatencyReport latency_;
  std::unique_ptr<tools::RegistrationReport> registration_;
  std::map<std::string, arphys::process_status_t> heartbeats_;
  MemoryWatch memory_;
};

}  // namespace arphys::launch
