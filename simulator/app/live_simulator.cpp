#include "simulator/app/live_simulator.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::sim {
namespace {

using Clock = std::chrono::steady_clock;

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
  const dynamics::World& world = core.world();
  for (int i = 0; i < world.body_count(); ++i) {
    const dynamics::BodyModel& body = world.body_model(i);
    const dynamics::BodyState& now = world.body_state(i);
    arphys::body_state_t b{};
    b.body_id = body.id;
    b.model = body.model;
    b.role = body.real ? arphys::body_state_t::ROLE_REAL : arphys::body_state_t::ROLE_VIRTUAL;
    b.motion = static_cast<int8_t>(body.motion);
    b.X_WB = msg::to_message(now.X_WB);
    msg::to_array(dynamics::origin_velocity(body, now), b.v_WB_m_s);
    msg::to_array(now.w_WB_rad_s, b.w_WB_rad_s);
    ws.bodies.push_back(b);
  }
  ws.num_bodies = static_cast<int32_t>(ws.bodies.size());
  const auto& bodies = world.model().bodies;
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

class LiveSimulator {
 public:
  LiveSimulator(const config::SceneConfig& scene, const LiveOptions& options)
      : scene_(scene),
        options_(options),
        core_(scene, options.core),
        bus_(options.lcm_url.empty() ? scene.lcm_url : options.lcm_url) {
    if (!options_.state_file.empty()) resume_from(options_.state_file, core_, recovery_);
  }

  void subscribe() {
    bus_.subscribe<arphys::object_poses_t>(
        scene_.channels.object_poses,
        [&](const arphys::object_poses_t& m, const lcm::ReceiveBuffer&, const std::string&) { core_.on_tracking(to_frame(m)); });
    bus_.subscribe<arphys::sim_command_t>(
        scene_.channels.sim_command,
        [&](const arphys::sim_command_t& m, const lcm::ReceiveBuffer&, const std::string&) { core_.on_command(to_request(m)); });
  }

  void run();

 private:
  double clock_time() const;
  double keep_within_max_lag();
  void step_to_clock();
  void publish_heartbeat(Clock::time_point now);

  const config::SceneConfig& scene_;
  LiveOptions options_;
  SimulatorCore core_;
  msg::Bus bus_;
  RecoveryReport recovery_;
  Clock::time_point start_ = Clock::now(), last_status_ = start_, last_checkpoint_ = start_;
  Clock::time_point last_drop_line_ = start_ - std::chrono::seconds(1);
  int64_t published_ = 0, steps_since_status_ = 0;
  double wall_clock_dropped_s_ = 0;  // the wall clock's share of --max-lag-s drops, and the time paused
  double stage_ms_since_status_ = 0;
  bool was_paused_ = false;
};

// Where the simulation should be: the newest capture's time, or the wall's.
double LiveSimulator::clock_time() const {
  if (options_.wall_clock) return std::chrono::duration<double>(Clock::now() - start_).count() - wall_clock_dropped_s_;
  return core_.clock_started() ? core_.sim_time_of(core_.newest_capture_utime()) : 0.0;
}

// Gives up what is past --max-lag-s and returns it. A tracked body covers what is given up
// in its next step, so it is given up as it accrues, step by step: a whole backlog at once
// would be a hard push.
double LiveSimulator::keep_within_max_lag() {
  const double excess_s = clock_time() - core_.sim_time_s() - options_.max_lag_s;
  if (options_.max_lag_s <= 0 || core_.paused() || !(excess_s > 0)) return 0.0;
  core_.drop_time(excess_s);
  wall_clock_dropped_s_ += excess_s;
  if (Clock::now() - last_drop_line_ >= std::chrono::seconds(1)) {
    std::fprintf(stderr,
                 "arphys-simulator: more than --max-lag-s %.3g s behind at simulation time %.2f s: %.2f s "
                 "given up so far, the virtual bodies run slow\n",
                 options_.max_lag_s, core_.sim_time_s(), core_.dropped_time_s());
    last_drop_line_ = Clock::now();
  }
  return excess_s;
}

// Steps up to the clock, publishing every step's world state.
void LiveSimulator::step_to_clock() {
  double target = clock_time();
  const double dt = scene_.time_step_s;
  while (!g_stop && core_.sim_time_s() + dt <= target + 1e-12 && !core_.paused()) {
    const int64_t step_start = msg::now_utime();
    core_.advance_to(core_.sim_time_s() + dt);
    const int64_t step_end = msg::now_utime();
    arphys::world_state_t ws = world_state(core_, step_start, step_end);
    ws.publish_utime = msg::now_utime();
    bus_.publish(scene_.channels.world_state, ws);
    ++published_;
    // Checked after every step: a simulator that runs behind steps for seconds in this
    // loop, and a kill then must not lose all of them.
    if (!options_.state_file.empty() && Clock::now() - last_checkpoint_ >= std::chrono::milliseconds(200)) {
      write_checkpoint(options_.state_file, ws);
      last_checkpoint_ = Clock::now();
    }
    ++steps_since_status_;
    stage_ms_since_status_ += 1e-3 * static_cast<double>(step_end - step_start);
    // The batch ends where it was to end, less what is given up: new frames wait for the
    // next batch, so a simulator that is always behind still gets to its heartbeat.
    // (Without --max-lag-s, input is taken between batches only, as a replay expects.)
    if (options_.max_lag_s > 0) {
      bus_.handle_pending();
      target -= keep_within_max_lag();
    }
  }
}

void LiveSimulator::publish_heartbeat(Clock::time_point now) {
  const double window_s = std::chrono::duration<double>(now - last_status_).count();
  arphys::process_status_t status =
      msg::heartbeat("simulator", std::string("gauss-ccd/") + (scene_.solver == "exact" ? "exact" : "iterative"),
                     std::chrono::duration<double>(now - start_).count(), bus_);
  status.rate_hz = steps_since_status_ / window_s;
  status.stage_duration_ms = steps_since_status_ ? stage_ms_since_status_ / steps_since_status_ : 0.0;
  status.published = published_;
  status.dropped = std::llround(core_.dropped_time_s() / scene_.time_step_s);  // steps given up (--max-lag-s)
  if (options_.max_lag_s > 0) msg::add_figure(status, "dropped_time_s", core_.dropped_time_s());
  status.rejected += core_.rejected_total();
  msg::add_figure(status, "bodies_left_world", static_cast<double>(core_.bodies_left_world()));
  if (scene_.sleep_after_s > 0) msg::add_figure(status, "bodies_asleep", core_.last_report().bodies_asleep);
  if (!options_.state_file.empty()) {
    msg::add_figure(status, "resumed_bodies", recovery_.recovered);
    msg::add_figure(status, "bodies_not_resumed", static_cast<double>(recovery_.lost.size()));
  }
  const auto lost = core_.lost_objects();
  status.state = core_.paused() ? "paused" : (lost.empty() ? "running" : "running, lost: " + lost.front());
  bus_.publish(scene_.channels.process_status, status);
  last_status_ = now;
  steps_since_status_ = 0;
  stage_ms_since_status_ = 0;
}

void LiveSimulator::run() {
  start_ = last_status_ = last_checkpoint_ = Clock::now();
  last_drop_line_ = start_ - std::chrono::seconds(1);
  std::fprintf(stderr, "arphys-simulator: scene %s, %d bodies, dt %.4g s, clock %s, tracking policy %s, LCM %s\n",
               scene_.name.c_str(), core_.world().body_count(), scene_.time_step_s,
               options_.wall_clock ? "wall" : "messages", to_string(options_.core.policy), bus_.url().c_str());
  while (!g_stop) {
    if (options_.duration_s > 0 && std::chrono::duration<double>(Clock::now() - start_).count() > options_.duration_s) break;
    bus_.handle_timeout_ms(static_cast<int>(std::max(1.0, 1e3 * scene_.time_step_s / 2)));
    bus_.handle_pending();
    // Resumed: on the wall clock, the time paused is not simulated either (the core maps
    // captures past it on its own).
    if (was_paused_ && !core_.paused() && options_.wall_clock)
      wall_clock_dropped_s_ += std::max(0.0, clock_time() - core_.sim_time_s());
    was_paused_ = core_.paused();
    keep_within_max_lag();
    step_to_clock();
    const auto now = Clock::now();
    if (now - last_status_ >= std::chrono::seconds(1)) publish_heartbeat(now);
  }
  std::fprintf(stderr, "arphys-simulator: %lld world states published, %.2f s of simulation given up (--max-lag-s), "
               "%lld messages received, %lld undecodable, %lld refused (last: %s)\n",
               static_cast<long long>(published_), core_.dropped_time_s(), static_cast<long long>(bus_.counters().received),
               static_cast<long long>(bus_.counters().decode_errors),
               static_cast<long long>(bus_.counters().rejected + core_.rejected_total()), core_.last_rejection().c_str());
}

}  // namespace

int run_live(const config::SceneConfig& scene, const LiveOptions& options) {
  std::unique_ptr<LiveSimulator> live;
  try {
    live = std::make_unique<LiveSimulator>(scene, options);
    live->subscribe();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-simulator: %s\n", e.what());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  live->run();
  return 0;
}

}  // namespace arphys::sim
