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
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "simulator/dynamics/memory_policy.hpp"
#include "simulator/process/simulator_core.hpp"

namespace {

using namespace arphys;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

sim::TrackingFrame to_frame(const arphys::object_poses_t& msg) {
  sim::TrackingFrame frame;
  frame.capture_utime = msg.utime;
  frame.seq = msg.seq;
  for (const auto& o : msg.objects) {
    sim::TrackedObject object;
    object.object_id = o.object_id;
    object.lost = o.status == arphys::object_pose_t::STATUS_LOST;
    object.world_valid = o.world_valid;
    if (object.world_valid && !object.lost) {
      const std::string problem = msg::pose_problem(o.X_WO);
      if (!problem.empty()) throw std::invalid_argument("object '" + o.object_id + "': " + problem);
      object.X_WO = msg::from_message(o.X_WO, o.object_id);
    }
    frame.objects.push_back(object);
  }
  return frame;
}

sim::SpawnRequest to_request(const arphys::sim_command_t& msg) {
  sim::SpawnRequest r;
  r.sender = msg.sender;
  r.seq = msg.seq;
  switch (msg.command) {
    case arphys::sim_command_t::COMMAND_SPAWN: r.kind = sim::SpawnRequest::Kind::kSpawn; break;
    case arphys::sim_command_t::COMMAND_REMOVE: r.kind = sim::SpawnRequest::Kind::kRemove; break;
    case arphys::sim_command_t::COMMAND_RESET: r.kind = sim::SpawnRequest::Kind::kReset; break;
    case arphys::sim_command_t::COMMAND_PAUSE: r.kind = sim::SpawnRequest::Kind::kPause; break;
    case arphys::sim_command_t::COMMAND_RESUME: r.kind = sim::SpawnRequest::Kind::kResume; break;
    default: throw std::invalid_argument("unknown command " + std::to_string(msg.command));
  }
  r.model = msg.model;
  r.body_id = msg.body_id;
  if (r.kind == sim::SpawnRequest::Kind::kSpawn) {
    r.X_WB = msg::from_message(msg.X_WB, "spawn pose");
    r.v_WB_m_s = msg::from_array(msg.v_WB_m_s);
    r.w_WB_rad_s = msg::from_array(msg.w_WB_rad_s);
  }
  return r;
}

arphys::world_state_t world_state(const sim::SimulatorCore& core, int64_t step_start, int64_t step_end) {
  arphys::world_state_t ws{};
  ws.utime = core.newest_capture_utime();
  ws.seq = core.newest_seq();
  ws.sim_time_s = core.sim_time_s();
  ws.scene_name = core.scene().name;
  ws.step_start_utime = step_start;
  ws.step_end_utime = step_end;
  for (const auto& body : core.world().bodies()) {
    arphys::body_state_t b{};
    b.body_id = body.id;
    b.model = body.model;
    b.role = body.real ? arphys::body_state_t::ROLE_REAL : arphys::body_state_t::ROLE_VIRTUAL;
    b.motion = static_cast<int8_t>(body.motion);
    b.X_WB = msg::to_message(body.X_WB);
    msg::to_array(body.origin_velocity(), b.v_WB_m_s);
    msg::to_array(body.w_WB_rad_s, b.w_WB_rad_s);
    ws.bodies.push_back(b);
  }
  ws.num_bodies = static_cast<int32_t>(ws.bodies.size());
  const auto& bodies = core.world().bodies();
  for (const auto& c : core.world().contacts()) {
    arphys::contact_t contact{};
    contact.body_a = bodies[c.body_a].id;
    contact.body_b = bodies[c.body_b].id;
    msg::to_array(0.5 * (c.feature.point_A_W + c.feature.point_B_W), contact.p_W_m);
    msg::to_array(c.feature.normal_W, contact.n_W);
    contact.time_of_impact_s = core.sim_time_s();
    contact.impulse_n_s = c.impulse_N_s;
    contact.separation_m = c.feature.distance_m;
    ws.contacts.push_back(contact);
  }
  for (const auto& c : core.proxy_contacts()) {
    arphys::contact_t contact{};
    contact.body_a = c.body_a;
    contact.body_b = c.body_b;
    msg::to_array(c.point_W, contact.p_W_m);
    msg::to_array(c.normal_W, contact.n_W);
    contact.time_of_impact_s = c.time_of_impact_s;
    ws.contacts.push_back(contact);
  }
  ws.num_contacts = static_cast<int32_t>(ws.contacts.size());
  return ws;
}

// The checkpoint is the last world state, in its LCM encoding, replaced atomically (write
// then rename) so a process killed mid-write leaves the previous one whole.
void write_checkpoint(const std::string& path, const arphys::world_state_t& ws) {
  const std::vector<uint8_t> bytes = msg::encode(ws);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) return;  // a full disk must not stop the simulation; the previous checkpoint stays
  }
  std::rename(tmp.c_str(), path.c_str());
}

// Resumes the virtual bodies of a checkpoint a previous run left; says what came back.
void resume_from(const std::string& path, sim::SimulatorCore& core, sim::RecoveryReport& report) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;  // first start: nothing to resume
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  arphys::world_state_t saved;
  if (saved.decode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0) {
    std::fprintf(stderr, "arphys-simulator: state file %s does not decode as a world state: starting the scene afresh\n",
                 path.c_str());
    return;
  }
  if (saved.scene_name != core.scene().name) {
    std::fprintf(stderr, "arphys-simulator: state file %s is of scene '%s', not '%s': starting the scene afresh\n",
                 path.c_str(), saved.scene_name.c_str(), core.scene().name.c_str());
    return;
  }
  std::vector<sim::RecoveredBody> bodies;
  for (const auto& b : saved.bodies) {
    // Virtual bodies, and tracked real ones (so tracking moves them on from where they were).
    const bool virtual_dynamic = b.role == arphys::body_state_t::ROLE_VIRTUAL && b.motion == arphys::body_state_t::MOTION_DYNAMIC;
    const bool tracked = b.role == arphys::body_state_t::ROLE_REAL && b.motion == arphys::body_state_t::MOTION_KINEMATIC;
    if (!virtual_dynamic && !tracked) continue;
    sim::RecoveredBody body;
    body.body_id = b.body_id;
    body.model = b.model;
    try {
      body.X_WB = msg::from_message(b.X_WB, b.body_id);
    } catch (const std::exception& e) {
      report.lost.push_back(b.body_id + ": " + e.what());
      continue;
    }
    body.v_WB_m_s = msg::from_array(b.v_WB_m_s);
    body.w_WB_rad_s = msg::from_array(b.w_WB_rad_s);
    bodies.push_back(body);
  }
  const sim::RecoveryReport recovered = core.recover(bodies);
  report.recovered += recovered.recovered;
  report.lost.insert(report.lost.end(), recovered.lost.begin(), recovered.lost.end());
  const double age_s = std::chrono::duration<double>(std::filesystem::file_time_type::clock::now() -
                                                     std::filesystem::last_write_time(path)).count();
  std::fprintf(stderr, "arphys-simulator: resumed %d virtual bodies from %s (saved %.2f s ago, at simulation time "
               "%.3f s; their motion since then is lost)%s\n",
               report.recovered, path.c_str(), age_s, saved.sim_time_s, report.lost.empty() ? "" : "; not resumed:");
  for (const auto& lost : report.lost) std::fprintf(stderr, "  %s\n", lost.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys simulator process: tracked poses and commands in (LCM), world state out.\n"
               "Steps continuous collision detection and Gauss least-constraint dynamics."};
  std::string scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml";
  std::string url, clock = "messages", policy;
  double duration_s = 0;
  sim::CoreOptions options;
  app.add_option("scene", scene_path, "scene YAML file")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL (default: the scene's lcm.url)");
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
  app.add_option("--duration", duration_s, "exit after this many wall-clock seconds (0: run until SIGINT)");
  double max_lag_s = 0;
  app.add_option("--max-lag-s", max_lag_s,
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
  std::string state_file;
  app.add_option("--state-file", state_file,
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
  std::unique_ptr<sim::SimulatorCore> core;
  std::unique_ptr<msg::Bus> bus;
  try {
    core = std::make_unique<sim::SimulatorCore>(scene, options);
    bus = std::make_unique<msg::Bus>(url.empty() ? scene.lcm_url : url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-simulator: %s\n", e.what());
    return 2;
  }
  sim::RecoveryReport recovery;
  if (!state_file.empty()) resume_from(state_file, *core, recovery);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  bus->subscribe<arphys::object_poses_t>(scene.channels.object_poses,
                                         [&](const arphys::object_poses_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                           core->on_tracking(to_frame(m));
                                         });
  bus->subscribe<arphys::sim_command_t>(scene.channels.sim_command,
                                        [&](const arphys::sim_command_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                          core->on_command(to_request(m));
                                        });

  const auto start = std::chrono::steady_clock::now();
  auto last_status = start, last_checkpoint = start;
  int64_t published = 0, steps_since_status = 0;
  double wall_clock_dropped_s = 0;  // the wall clock's share of --max-lag-s drops, and the time paused
  bool was_paused = false;
  auto last_drop_line = start - std::chrono::seconds(1);
  double stage_ms_since_status = 0;
  std::fprintf(stderr, "arphys-simulator: scene %s, %zu bodies, dt %.4g s, clock %s, tracking policy %s, LCM %s\n",
               scene.name.c_str(), core->world().bodies().size(), scene.time_step_s, clock.c_str(),
               sim::to_string(options.policy), bus->url().c_str());
  // Where the simulation should be: the newest capture's time, or the wall's.
  const auto clock_time = [&] {
    if (clock == "wall")
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - wall_clock_dropped_s;
    return core->clock_started() ? core->sim_time_of(core->newest_capture_utime()) : 0.0;
  };
  // Gives up what is past --max-lag-s and returns it. A tracked body covers what is given up
  // in its next step, so it is given up as it accrues, step by step: a whole backlog at once
  // would be a hard push.
  const auto keep_within_max_lag = [&]() -> double {
    const double excess_s = clock_time() - core->sim_time_s() - max_lag_s;
    if (max_lag_s <= 0 || core->paused() || !(excess_s > 0)) return 0.0;
    core->drop_time(excess_s);
    wall_clock_dropped_s += excess_s;
    if (std::chrono::steady_clock::now() - last_drop_line >= std::chrono::seconds(1)) {
      std::fprintf(stderr,
                   "arphys-simulator: more than --max-lag-s %.3g s behind at simulation time %.2f s: %.2f s "
                   "given up so far, the virtual bodies run slow\n",
                   max_lag_s, core->sim_time_s(), core->dropped_time_s());
      last_drop_line = std::chrono::steady_clock::now();
    }
    return excess_s;
  };
  while (!g_stop) {
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (duration_s > 0 && elapsed_s > duration_s) break;
    bus->handle_timeout_ms(static_cast<int>(std::max(1.0, 1e3 * scene.time_step_s / 2)));
    bus->handle_pending();
    // Resumed: on the wall clock, the time paused is not simulated either (the core maps
    // captures past it on its own).
    if (was_paused && !core->paused() && clock == "wall")
      wall_clock_dropped_s += std::max(0.0, clock_time() - core->sim_time_s());
    was_paused = core->paused();
    keep_within_max_lag();
    double target = clock_time();
    while (!g_stop && core->sim_time_s() + scene.time_step_s <= target + 1e-12 && !core->paused()) {
      const int64_t step_start = msg::now_utime();
      core->advance_to(core->sim_time_s() + scene.time_step_s);
      const int64_t step_end = msg::now_utime();
      arphys::world_state_t ws = world_state(*core, step_start, step_end);
      ws.publish_utime = msg::now_utime();
      bus->publish(scene.channels.world_state, ws);
      ++published;
      // Checked after every step: a simulator that runs behind steps for seconds in this
      // loop, and a kill then must not lose all of them.
      if (!state_file.empty() && std::chrono::steady_clock::now() - last_checkpoint >= std::chrono::milliseconds(200)) {
        write_checkpoint(state_file, ws);
        last_checkpoint = std::chrono::steady_clock::now();
      }
      ++steps_since_status;
      stage_ms_since_status += 1e-3 * static_cast<double>(step_end - step_start);
      // The batch ends where it was to end, less what is given up: new frames wait for the
      // next batch, so a simulator that is always behind still gets to its heartbeat.
      // (Without --max-lag-s, input is taken between batches only, as a replay expects.)
      if (max_lag_s > 0) {
        bus->handle_pending();
        target -= keep_within_max_lag();
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_status >= std::chrono::seconds(1)) {
      const double window_s = std::chrono::duration<double>(now - last_status).count();
      arphys::process_status_t status =
          msg::heartbeat("simulator", std::string("gauss-ccd/") + (scene.solver == "exact" ? "exact" : "iterative"),
                         std::chrono::duration<double>(now - start).count(), *bus);
      status.rate_hz = steps_since_status / window_s;
      status.stage_duration_ms = steps_since_status ? stage_ms_since_status / steps_since_status : 0.0;
      status.published = published;
      status.dropped = std::llround(core->dropped_time_s() / scene.time_step_s);  // steps given up (--max-lag-s)
      if (max_lag_s > 0) msg::add_figure(status, "dropped_time_s", core->dropped_time_s());
      status.rejected += core->rejected_total();
      msg::add_figure(status, "bodies_left_world", static_cast<double>(core->bodies_left_world()));
      if (scene.sleep_after_s > 0) msg::add_figure(status, "bodies_asleep", core->last_report().bodies_asleep);
      if (!state_file.empty()) {
        msg::add_figure(status, "resumed_bodies", recovery.recovered);
        msg::add_figure(status, "bodies_not_resumed", static_cast<double>(recovery.lost.size()));
      }
      const auto lost = core->lost_objects();
      status.state = core->paused() ? "paused" : (lost.empty() ? "running" : "running, lost: " + lost.front());
      bus->publish(scene.channels.process_status, status);
      last_status = now;
      steps_since_status = 0;
      stage_ms_since_status = 0;
    }
  }
  std::fprintf(stderr, "arphys-simulator: %lld world states published, %.2f s of simulation given up (--max-lag-s), "
               "%lld messages received, %lld undecodable, %lld refused (last: %s)\n",
               static_cast<long long>(published), core->dropped_time_s(), static_cast<long long>(bus->counters().received),
               static_cast<long long>(bus->counters().decode_errors),
               static_cast<long long>(bus->counters().rejected + core->rejected_total()), core->last_rejection().c_str());
  return 0;
}
