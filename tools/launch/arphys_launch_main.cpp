// arphys-launch: the pipeline with one command. Starts the processes of a scene (the
// synthetic camera or a real source, the tracker, the simulator, the renderer, and
// optionally lcm-logger), spawns virtual objects as a user would, prints a status line
// per process from their heartbeats, measures latency per stage from the messages
// themselves, stops everything cleanly, and exits non-zero naming a process that died.
#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <csignal>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "arphys/ground_truth_t.hpp"
#include "arphys/image_t.hpp"
#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "configs/loader/camera_script.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "simulator/geometry/triangle_mesh.hpp"
#include "tools/launch/latency_report.hpp"
#include "tools/launch/main_job_throws.hpp"
#include "tools/launch/registration_report.hpp"

extern char** environ;

namespace {

using namespace arphys;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

struct Child {
  std::string name;
  std::vector<std::string> args;
  pid_t pid = -1;
  bool exited = false;
  int status = 0;
};

pid_t spawn(const std::vector<std::string>& args, const std::string& log_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!log_path.empty()) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  }
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

std::string default_script_for(const config::SceneConfig& scene) {
  const std::string dir = config::default_config_dir() + "/synthetic/";
  if (scene.name == "bunny_box_table") return dir + "box_push.yaml";
  if (scene.name == "spoon_teacup") return dir + "spoon_approach.yaml";
  return "";
}

// Resident memory of each process over the run, from its heartbeats: the figure a leak
// shows in. The baseline is taken once the process has run warm_up_s (caches, the
// first frames and meshes are loaded by then); a restarted process starts a new one.
struct MemoryWatch {
  double warm_up_s = 10;
  struct Process {
    int32_t pid = 0;
    double baseline_mb = -1, baseline_uptime_s = 0, last_mb = 0, last_uptime_s = 0, max_mb = 0;
  };
  std::map<std::string, Process> processes;

  void on_heartbeat(const arphys::process_status_t& status) {
    const std::optional<double> rss = msg::figure(status, "rss_mb");
    if (!rss || *rss < 0) return;
    const double rss_mb = *rss;
    Process& p = processes[status.name];
    if (p.pid != status.pid) p = Process{status.pid};
    if (p.baseline_mb < 0 && status.uptime_s >= warm_up_s) {
      p.baseline_mb = rss_mb;
      p.baseline_uptime_s = status.uptime_s;
    }
    p.last_mb = rss_mb;
    p.last_uptime_s = status.uptime_s;
    p.max_mb = std::max(p.max_mb, rss_mb);
  }

  nlohmann::json to_json() const {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [name, p] : processes) {
      nlohmann::json entry{{"pid", p.pid}, {"rss_mb_end", p.last_mb}, {"rss_mb_max", p.max_mb}};
      if (p.baseline_mb >= 0) {
        entry["rss_mb_after_warm_up"] = p.baseline_mb;
        entry["growth_mb"] = p.last_mb - p.baseline_mb;
        entry["over_s"] = p.last_uptime_s - p.baseline_uptime_s;
      }
      out[name] = entry;
    }
    return out;
  }
};

// The tracked real object whose overlay registration is measured (the first kinematic
// real object) and the corners of its bounding box, object frame.
std::unique_ptr<tools::RegistrationReport> registration_for(const config::SceneConfig& scene) {
  if (scene.camera_file.empty()) return nullptr;
  for (const auto& o : scene.objects) {
    if (o.role != config::Role::kReal || o.motion != config::Motion::kKinematic) continue;
    Eigen::AlignedBox3d box;
    switch (o.collision.type) {
      case config::ShapeType::kBox: box = Eigen::AlignedBox3d(-0.5 * o.collision.size_m, 0.5 * o.collision.size_m); break;
      case config::ShapeType::kSphere:
        box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-o.collision.radius_m), Eigen::Vector3d::Constant(o.collision.radius_m));
        break;
      case config::ShapeType::kMesh: box = geometry::load_mesh(o.collision.mesh_path, o.collision.scale).bounds(); break;
      case config::ShapeType::kConvexSet:
        box = geometry::load_mesh(o.collision.pieces_path, o.collision.scale).bounds();
        break;
      case config::ShapeType::kPlane: continue;
    }
    std::vector<Eigen::Vector3d> corners;
    for (int i = 0; i < 8; ++i) corners.push_back(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)));
    return std::make_unique<tools::RegistrationReport>(config::load_camera(scene.camera_file), o.id, corners);
  }
  return nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys-launch: the synthetic camera (or a real source), tracker, simulator and renderer of a scene,\n"
               "started together, watched, measured and stopped together."};
  std::string scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml";
  std::string camera = "synthetic", script_path, tracker_impl = "apriltag", out_dir, only, url, build_dir = ARPHYS_BUILD_DIR;
  std::string tracker_filter = "constant_velocity";
  double duration_s = 20, spawn_every_s = 1.0, renderer_wait_ms = 0, sim_max_lag_s = 0.1;
  int sim_threads = 1;
  bool record = false, restart = false;
  double receive_loss = 0;
  std::string tracking_policy;
  app.add_option("scene", scene_path, "scene YAML")->capture_default_str();
  app.add_option("--camera", camera, "synthetic (the scene's camera script), /dev/videoN, or a video file")
      ->capture_default_str();
  app.add_option("--script", script_path, "camera script for --camera synthetic (default: the scene's, "
                                          "configs/synthetic/box_push.yaml or spoon_approach.yaml)");
  app.add_option("--tracker", tracker_impl, "tracker implementation")->check(CLI::IsMember({"apriltag", "aruco"}))
      ->capture_default_str();
  app.add_option("--tracker-filter", tracker_filter,
                 "the tracker's pose filter (tracker --filter): constant_velocity keeps a noisy tracked box from "
                 "pushing faster than it moves")
      ->check(CLI::IsMember({"none", "one_euro", "constant_velocity"}))
      ->capture_default_str();
  app.add_option("--duration", duration_s, "seconds to run (the synthetic camera plays this much of its script; a camera drawing slower than real time is waited for, up to 20 s more)")->capture_default_str();
  app.add_option("--out", out_dir, "write overlay.avi, latency.json, process logs (and run.lcmlog) here");
  app.add_flag("--restart", restart, "restart a process that dies (reported, counted) instead of stopping the run");
  app.add_flag("--record", record, "record all traffic with lcm-logger to OUT/run.lcmlog");
  app.add_option("--only", only, "comma-separated subset to start: camera,tracker,simulator,renderer (other machines "
                                 "run the rest)");
  app.add_option("--spawn-every", spawn_every_s, "spawn the scene's first dynamic virtual model every S seconds, "
                                                 "thrown onto the table (0: none)")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL for every process (default: the scene's)");
  app.add_option("--tracking-policy", tracking_policy, "override the scene's tracking policy in the simulator")
      ->check(CLI::IsMember({"delay", "extrapolate"}));
  double catch_up_factor = 0;
  app.add_option("--catch-up-factor", catch_up_factor,
                 "the simulator's --catch-up-factor: a re-acquired track is caught up with at this many times the "
                 "object's own speed over the gap (default: the simulator's, 2)")
      ->check(CLI::Range(1.0, 100.0));
  app.add_option("--renderer-wait-ms", renderer_wait_ms,
                 "the renderer holds each frame up to this long for the world state computed from it (renderer "
                 "--wait-ms): the overlay shows the frame's own world, later")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  app.add_option("--sim-max-lag-s", sim_max_lag_s,
                 "a simulator falling further behind the camera than this gives the backlog up (its virtual bodies "
                 "run slow for a moment) instead of lagging ever more (arphys-simulator --max-lag-s; 0: never)")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--sim-threads", sim_threads,
                 "worker threads of the simulator's collision queries (arphys-simulator --threads; the world states "
                 "are the same for any number)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--receive-loss", receive_loss,
                 "fault injection: every started process drops this fraction of the messages it receives, at random "
                 "(ARPHYS_FAULT_RECEIVE_LOSS)")
      ->check(CLI::Range(0.0, 0.99));
  app.add_option("--build", build_dir, "build directory holding the executables")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  config::SceneConfig scene;
  config::CameraScriptConfig script;
  try {
    scene = config::load_scene(scene_path);
    if (camera == "synthetic") {
      if (script_path.empty()) script_path = default_script_for(scene);
      if (script_path.empty()) throw std::invalid_argument("scene " + scene.name + " has no default camera script: give --script");
      script = config::load_camera_script(script_path);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-launch: %s\n", e.what());
    return 2;
  }
  if (url.empty()) url = scene.lcm_url;
  auto wanted = [&](const std::string& name) { return only.empty() || ("," + only + ",").find("," + name + ",") != std::string::npos; };
  if (!out_dir.empty()) std::filesystem::create_directories(out_dir);
  auto log_of = [&](const std::string& name) { return out_dir.empty() ? std::string() : out_dir + "/" + name + ".log"; };
  // Children outlive the run; the launcher stops them, so any earlier exit is a death.
  const std::string seconds = std::to_string(duration_s + 30);

  std::unique_ptr<msg::Bus> bus;
  try {
    bus = std::make_unique<msg::Bus>(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-launch: %s\n", e.what());
    return 2;
  }
  // Watch everything from the start.
  tools::LatencyReport latency;
  std::unique_ptr<tools::RegistrationReport> registration;
  try {
    if (camera == "synthetic") registration = registration_for(scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-launch: no registration error measured: %s\n", e.what());
  }
  if (registration) {
    bus->subscribe<arphys::ground_truth_t>(scene.channels.ground_truth, [&](const arphys::ground_truth_t& m,
                                                                           const lcm::ReceiveBuffer&,
                                                                           const std::string&) { registration->on_ground_truth(m); });
  }
  std::map<std::string, arphys::process_status_t> heartbeats;
  MemoryWatch memory;
  bus->subscribe<arphys::image_t>(scene.channels.camera_image, [&](const arphys::image_t& m, const lcm::ReceiveBuffer&,
                                                                  const std::string&) { latency.on_image(m); });
  bus->subscribe<arphys::marker_detections_t>(
      scene.channels.marker_detections,
      [&](const arphys::marker_detections_t& m, const lcm::ReceiveBuffer&, const std::string&) { latency.on_detections(m); });
  bus->subscribe<arphys::object_poses_t>(scene.channels.object_poses, [&](const arphys::object_poses_t& m,
                                                                         const lcm::ReceiveBuffer&,
                                                                         const std::string&) { latency.on_poses(m); });
  bus->subscribe<arphys::world_state_t>(scene.channels.world_state, [&](const arphys::world_state_t& m,
                                                                       const lcm::ReceiveBuffer&,
                                                                       const std::string&) {
    latency.on_world_state(m);
    if (registration) registration->on_world_state(m);
  });
  bus->subscribe<arphys::render_status_t>(scene.channels.render_status, [&](const arphys::render_status_t& m,
                                                                           const lcm::ReceiveBuffer&,
                                                                           const std::string&) {
    latency.on_render_status(m);
    if (registration) registration->on_render_status(m);
  });
  bus->subscribe<arphys::process_status_t>(scene.channels.process_status, [&](const arphys::process_status_t& m,
                                                                             const lcm::ReceiveBuffer&, const std::string&) {
    heartbeats[m.name] = m;
    memory.on_heartbeat(m);
  });
  // Set after the launcher's own bus exists: only the children lose messages.
  if (receive_loss > 0) setenv("ARPHYS_FAULT_RECEIVE_LOSS", std::to_string(receive_loss).c_str(), 1);

  std::vector<Child> children;
  std::map<std::string, int> restarts;
  auto start_child = [&](const std::string& name, const std::vector<std::string>& args) {
    Child c;
    c.name = name;
    c.args = args;
    c.pid = spawn(args, log_of(name));
    if (c.pid <= 0) {
      std::fprintf(stderr, "arphys-launch: cannot start %s (%s)\n", name.c_str(), args[0].c_str());
      g_stop = true;
    }
    children.push_back(c);
  };
  const std::string b = build_dir;
  if (record && !out_dir.empty()) start_child("recorder", {"lcm-logger", "--lcm-url=" + url, "--force", out_dir + "/run.lcmlog"});
  // The simulator keeps its last world state in a file, so a restarted one resumes the
  // virtual bodies; a new run starts from the scene.
  const std::string state_file = (out_dir.empty() ? std::filesystem::temp_directory_path().string() + "/arphys-launch-" +
                                                         std::to_string(getpid())
                                                   : out_dir + "/simulator") + ".state";
  std::filesystem::remove(state_file);
  if (wanted("simulator")) {
    std::vector<std::string> args{b + "/simulator/app/arphys-simulator", scene.file, "--lcm-url", url, "--duration", seconds,
                                  "--state-file", state_file};
    if (!tracking_policy.empty()) args.insert(args.end(), {"--tracking-policy", tracking_policy});
    if (catch_up_factor > 0) args.insert(args.end(), {"--catch-up-factor", std::to_string(catch_up_factor)});
    if (sim_max_lag_s > 0) args.insert(args.end(), {"--max-lag-s", std::to_string(sim_max_lag_s)});
    if (sim_threads > 1) args.insert(args.end(), {"--threads", std::to_string(sim_threads)});
    start_child("simulator", args);
  }
  if (wanted("renderer")) {
    std::vector<std::string> args{b + "/renderer/app/renderer", "--scene", scene.file, "--lcm-url", url, "--duration", seconds};
    if (renderer_wait_ms > 0) args.insert(args.end(), {"--wait-ms", std::to_string(renderer_wait_ms)});
    if (!out_dir.empty()) {
      args.insert(args.end(), {"--video", out_dir + "/overlay.avi", "--png-dir", out_dir + "/snapshots", "--png-every", "90"});
    }
    if (camera == "synthetic") {
      const auto t = script.X_WC.translation();
      const auto q = Eigen::Quaterniond(script.X_WC.linear());
      std::ostringstream pose;
      pose << t.x() << " " << t.y() << " " << t.z() << " " << q.w() << " " << q.x() << " " << q.y() << " " << q.z();
      args.insert(args.end(), {"--camera-pose", pose.str()});
    }
    start_child("renderer", args);
  }
  if (wanted("tracker")) {
    std::vector<std::string> args{b + "/tracker/app/tracker", "--scene", scene.file, "--lcm-url", url, "--impl", tracker_impl,
                                  "--filter", tracker_filter, "--duration", seconds};
    if (camera != "synthetic") args.insert(args.end(), {"--source", camera, "--publish-images", "--pace"});
    start_child("tracker", args);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // let subscribers join before frames flow
  if (camera == "synthetic" && wanted("camera")) {
    start_child("camera", {b + "/tools/synthetic_camera/arphys-synthetic-camera", script.file, "--lcm-url", url,
                           "--duration", std::to_string(duration_s)});
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  // The first dynamic virtual model is what a user throws in (the bunny).
  std::string spawn_model;
  int64_t spawn_limit = 0;  // the scene's max_instances, less those it starts with
  if (const config::ObjectConfig* model = launch::thrown_model(scene)) {
    spawn_model = model->id;
    spawn_limit = model->max_instances - static_cast<int64_t>(model->spawn_at_start.size());
  }
  launch::MainJobThrows throws;
  int64_t spawn_seq = 0;
  const auto start = std::chrono::steady_clock::now();
  auto last_line = start, last_spawn = start;
  // After the camera's last frame the run waits until no frame message has come for
  // kSettledS (the pipeline has carried that frame through and lcm-logger has it), at
  // most kDrainS.
  constexpr double kDrainS = 2.5, kSettledS = 0.5, kCameraLateLimitS = 20.0;
  int64_t frame_messages = -1;
  std::chrono::steady_clock::time_point last_frame_message = start;
  std::string drain_ended_by;
  double drain_s = 0;  // from the camera's end to the run's
  std::ptrdiff_t camera_child = -1;
  for (std::size_t i = 0; i < children.size(); ++i) {
    if (children[i].name == "camera") camera_child = static_cast<std::ptrdiff_t>(i);
  }
  std::optional<std::chrono::steady_clock::time_point> camera_done;
  std::string died;
  while (!g_stop) {
    bus->handle_timeout_ms(20);
    bus->handle_pending();
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start).count();
    // The run is the synthetic camera's script: it ends when the camera has published its
    // last frame and the pipeline has had time to carry it to the overlay. A camera that
    // draws slower than its frame rate (a loaded machine) is waited for, up to a bound; a
    // source on another machine or a real camera: the given duration.
    if (camera_child >= 0) {
      const Child& c = children[static_cast<std::size_t>(camera_child)];
      if (c.exited && !camera_done) camera_done = now;
      if (latency.frame_messages() != frame_messages) {
        frame_messages = latency.frame_messages();
        last_frame_message = now;
      }
      if (camera_done) {
        drain_s = std::chrono::duration<double>(now - *camera_done).count();
        const double quiet_s = std::chrono::duration<double>(now - std::max(last_frame_message, *camera_done)).count();
        if (quiet_s > kSettledS || drain_s > kDrainS) {
          drain_ended_by = quiet_s > kSettledS ? "settled" : "drain_limit";
          break;
        }
      }
      if (elapsed > duration_s + kCameraLateLimitS) {
        std::fprintf(stderr, "arphys-launch: the camera is still playing %.0f s after its script's end; stopping\n",
                     kCameraLateLimitS);
        break;
      }
    } else if (elapsed > duration_s + kDrainS) {
      break;
    }
    for (auto& c : children) {
      if (c.exited || c.pid <= 0) continue;
      if (waitpid(c.pid, &c.status, WNOHANG) == c.pid) {
        c.exited = true;
        // The frame source ends on its own: the synthetic camera after its script, the
        // tracker at the end of a video file. Anything else leaving early is a death.
        const bool source = c.name == "camera" || (c.name == "tracker" && camera != "synthetic" &&
                                                   camera.rfind("/dev/video", 0) != 0);
        const bool expected = source && WIFEXITED(c.status) && WEXITSTATUS(c.status) == 0;
        if (expected) continue;
        if (restart && !g_stop) {
          // The others keep running; the process comes back on the same channels and
          // resynchronises from the traffic (the simulator resumes its virtual bodies from
          // its state file). What it writes goes to new files: nothing recorded is lost.
          const int n = ++restarts[c.name];
          const std::string log = log_of(c.name).empty() ? std::string() : out_dir + "/" + c.name + "." +
                                                                                  std::to_string(n) + ".log";
          auto renamed = [n](std::string path, const std::string& extension) {
            return path.substr(0, path.size() - extension.size()) + "." + std::to_string(n) + extension;
          };
          if (c.name == "recorder") c.args.back() = renamed(out_dir + "/run.lcmlog", ".lcmlog");
          for (std::size_t i = 0; i + 1 < c.args.size(); ++i) {
            if (c.args[i] == "--video") c.args[i + 1] = renamed(out_dir + "/overlay.avi", ".avi");
          }
          std::fprintf(stderr, "arphys-launch: %s died (%s %d), restarting it (restart %d)\n", c.name.c_str(),
                       WIFSIGNALED(c.status) ? "signal" : "exit code",
                       WIFSIGNALED(c.status) ? WTERMSIG(c.status) : WEXITSTATUS(c.status), restarts[c.name]);
          c.pid = spawn(c.args, log);
          c.exited = c.pid <= 0;
          continue;
        }
        if (died.empty()) died = c.name;
      }
    }
    if (!died.empty()) break;
    if (!spawn_model.empty() && spawn_every_s > 0 && wanted("simulator") && spawn_seq < spawn_limit &&
        std::chrono::duration<double>(now - last_spawn).count() >= spawn_every_s && elapsed < duration_s) {
      arphys::sim_command_t c{};
      c.utime = msg::now_utime();
      c.seq = ++spawn_seq;
      c.sender = "arphys-launch";
      c.command = arphys::sim_command_t::COMMAND_SPAWN;
      c.model = spawn_model;
      const launch::Throw thrown = throws.next();
      c.X_WB = msg::to_message(thrown.X_WB);
      std::copy(thrown.v_WB_m_s.data(), thrown.v_WB_m_s.data() + 3, c.v_WB_m_s);
      bus->publish(scene.channels.sim_command, c);
      last_spawn = now;
    }
    if (now - last_line >= std::chrono::seconds(1)) {
      std::ostringstream line;
      line.setf(std::ios::fixed);
      line.precision(1);
      line << "t " << elapsed << " s";
      for (const auto& [name, s] : heartbeats) {
        line << " | " << name << " " << s.rate_hz << " Hz " << s.stage_duration_ms << " ms";
        if (name == "simulator" && s.dropped) {
          // The simulator's drops are steps of simulation given up (--sim-max-lag-s).
          line << " gave up " << s.dropped << " steps";
        } else if (s.dropped) {
          line << " drop " << s.dropped;
        }
        if (s.rejected) line << " rej " << s.rejected;
      }
      std::fprintf(stderr, "%s\n", line.str().c_str());
      last_line = now;
    }
  }
  for (auto& c : children) {
    if (!c.exited && c.pid > 0) kill(c.pid, SIGTERM);
  }
  for (auto& c : children) {
    if (!c.exited && c.pid > 0) waitpid(c.pid, &c.status, 0);
  }

  nlohmann::json report = latency.to_json();
  report["scene"] = scene.name;
  report["tracker"] = tracker_impl;
  report["duration_s"] = duration_s;
  report["restarts"] = restarts;
  report["memory"] = memory.to_json();
  report["receive_loss"] = receive_loss;
  report["tracking_policy"] = tracking_policy.empty() ? scene.tracking_policy : tracking_policy;
  // How the run ended after the camera's last frame: "settled" (no frame message for
  // kSettledS), "drain_limit" (still busy kDrainS later); null without a synthetic camera
  // or when it ended otherwise (a death, a signal, the camera's late limit).
  report["drain"] = {{"ended_by", drain_ended_by.empty() ? nlohmann::json() : nlohmann::json(drain_ended_by)},
                     {"seconds", drain_s}};
  // The simulation time the simulator gave up to keep within --sim-max-lag-s of the camera.
  report["simulator"] = {{"max_lag_s", sim_max_lag_s}, {"dropped_time_s", nullptr}};
  if (const auto it = heartbeats.find("simulator"); it != heartbeats.end()) {
    if (const auto dropped_s = msg::figure(it->second, "dropped_time_s")) report["simulator"]["dropped_time_s"] = *dropped_s;
  }
  if (registration) {
    report["registration"] = registration->to_json();
    const auto& r = report["registration"];
    if (r["count"].get<int>() > 0) {
      std::printf("overlay registration of '%s': p50 %.2f px, p95 %.2f px, max %.2f px over %d frames\n",
                  r["object"].get<std::string>().c_str(), r["p50_px"].get<double>(), r["p95_px"].get<double>(),
                  r["max_px"].get<double>(), r["count"].get<int>());
    }
  }
  latency.print();
  if (report["simulator"]["dropped_time_s"].is_number() && report["simulator"]["dropped_time_s"].get<double>() > 0) {
    std::printf("simulator: gave up %.2f s of simulation to stay within %.3g s of the camera (--sim-max-lag-s)\n",
                report["simulator"]["dropped_time_s"].get<double>(), sim_max_lag_s);
  }
  if (!out_dir.empty()) {
    std::ofstream(out_dir + "/latency.json") << report.dump(2) << "\n";
    latency.write_samples_csv(out_dir + "/latency_samples.csv");  // for tools/launch/latency_cdf.gp
    std::printf("written: %s/overlay.avi, %s/latency.json%s\n", out_dir.c_str(), out_dir.c_str(),
                record ? (", " + out_dir + "/run.lcmlog").c_str() : "");
  }
  for (const auto& [name, p] : memory.processes) {
    if (p.baseline_mb >= 0) {
      std::fprintf(stderr, "memory %-10s %.1f MB after warm-up, %+.2f MB over %.0f s\n", name.c_str(), p.baseline_mb,
                   p.last_mb - p.baseline_mb, p.last_uptime_s - p.baseline_uptime_s);
    }
  }
  if (out_dir.empty()) std::filesystem::remove(state_file);  // a temporary one
  if (!died.empty()) {
    std::fprintf(stderr, "arphys-launch: %s died unexpectedly%s\n", died.c_str(),
                 out_dir.empty() ? "" : (" (see " + log_of(died) + ")").c_str());
    return 1;
  }
  return 0;
}
