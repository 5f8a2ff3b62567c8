// arphys-launch: the pipeline with one command. Starts the processes of a scene (the
// synthetic camera or a real source, the tracker, the simulator, the renderer, and
// optionally lcm-logger), spawns virtual objects as a user would, prints a status line
// per process from their heartbeats, measures latency per stage from the messages
// themselves, stops everything cleanly, and exits non-zero naming a process that died.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "lcmtypes/msg/bus.hpp"
#include "tools/launch/main_job_spawner.hpp"
#include "tools/launch/process_commands.hpp"
#include "tools/launch/run_end.hpp"
#include "tools/launch/run_watch.hpp"
#include "tools/launch/supervisor.hpp"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  using namespace arphys;
  CLI::App app{"arphys-launch: the synthetic camera (or a real source), tracker, simulator and renderer of a scene,\n"
               "started together, watched, measured and stopped together."};
  launch::LaunchOptions o;
  o.scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml";
  o.build_dir = ARPHYS_BUILD_DIR;
  launch::add_launch_options(app, o);
  CLI11_PARSE(app, argc, argv);
  config::SceneConfig scene;
  config::CameraScriptConfig script;
  std::unique_ptr<msg::Bus> bus;
  const bool synthetic = o.camera == "synthetic";
  try {
    scene = config::load_scene(o.scene_path);
    if (synthetic) {
      if (o.script_path.empty()) o.script_path = launch::default_script_for(scene);
      if (o.script_path.empty()) throw std::invalid_argument("scene " + scene.name + " has no default camera script: give --script");
      script = config::load_camera_script(o.script_path);
    }
    bus = std::make_unique<msg::Bus>(o.lcm_url.empty() ? scene.lcm_url : o.lcm_url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-launch: %s\n", e.what());
    return 2;
  }
  if (!o.out_dir.empty()) std::filesystem::create_directories(o.out_dir);
  launch::RunWatch watch(*bus, scene, synthetic);  // everything watched from the start
  // Set after the launcher's own bus exists: only the children lose messages.
  if (o.receive_loss > 0) setenv("ARPHYS_FAULT_RECEIVE_LOSS", std::to_string(o.receive_loss).c_str(), 1);
  // The simulator keeps its last world state in a file, so a restarted one resumes the
  // virtual bodies; a new run starts from the scene.
  const std::string state_file = (o.out_dir.empty() ? std::filesystem::temp_directory_path().string() +
                                                          "/arphys-launch-" + std::to_string(getpid())
                                                    : o.out_dir + "/simulator") + ".state";
  std::filesystem::remove(state_file);
  launch::Supervisor children(o.out_dir);
  for (const launch::ProcessCommand& command : launch::process_commands(o, scene, synthetic ? &script : nullptr, state_file)) {
    // Subscribers join before frames flow.
    if (command.name == "camera") std::this_thread::sleep_for(std::chrono::milliseconds(800));
    if (!children.start(command.name, command.args)) g_stop = true;
  }
  if (children.find("view"))
    std::printf(
        "arphys-launch: the run in a browser at http://127.0.0.1:%d/ (Foxglove, Lichtblick: ws://127.0.0.1:%d)\n",
        o.view_port, o.view_port);
  std::fflush(stdout);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  launch::MainJobSpawner spawner(scene, o.spawn_every_s, o.wanted("simulator"));
  launch::RunEnd end(o.duration_s, synthetic && children.find("camera"));
  const auto start = std::chrono::steady_clock::now();
  double last_line_s = 0;
  std::string died;
  const auto expected = [&](const launch::Child& c) {
    return launch::ends_by_itself(c.name, o) && WIFEXITED(c.status) && WEXITSTATUS(c.status) == 0;
  };
  while (!g_stop) {
    bus->handle_timeout_ms(20);
    bus->handle_pending();
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const launch::Child* camera = children.find("camera");
    if (end.over(elapsed_s, camera && camera->exited, watch.frame_messages())) break;
    died = children.poll(o.restart && !g_stop, expected);
    if (!died.empty()) break;
    if (elapsed_s < o.duration_s) spawner.maybe_spawn(*bus, scene.channels.sim_command, elapsed_s);
    if (elapsed_s - last_line_s >= 1.0) {
      std::fprintf(stderr, "%s\n", watch.status_line(elapsed_s).c_str());
      last_line_s = elapsed_s;
    }
  }
  if (end.why() == "camera_late") {
    std::fprintf(stderr, "arphys-launch: the camera is still playing %.0f s after its script's end; stopping\n",
                 launch::RunEnd::kCameraLateLimitS);
  }
  children.stop_all();
  const bool drained = end.why() == "settled" || end.why() == "drain_limit";
  const nlohmann::json report = watch.report(o, scene, children.restarts(), drained ? end.why() : "", end.drain_s());
  watch.print(report);
  if (!o.out_dir.empty()) {
    std::ofstream(o.out_dir + "/latency.json") << report.dump(2) << "\n";
    watch.write_samples_csv(o.out_dir + "/latency_samples.csv");  // for tools/launch/latency_cdf.gp
    std::printf("written: %s/overlay.avi, %s/latency.json%s\n", o.out_dir.c_str(), o.out_dir.c_str(),
                o.record ? (", " + o.out_dir + "/run.lcmlog").c_str() : "");
  }
  if (o.out_dir.empty()) std::filesystem::remove(state_file);  // a temporary one
  if (!died.empty()) {
    std::fprintf(stderr, "arphys-launch: %s died unexpectedly%s\n", died.c_str(),
                 o.out_dir.empty() ? "" : (" (see " + children.log_of(died) + ")").c_str());
    return 1;
  }
  return 0;
}
