#pragma once
// The simulator process without its transport: tracked poses and commands in, a
// stepped world out. Everything the process receives is validated here, and every
// rejection is counted with its reason, so the LCM executable stays a thin wiring and
// the behaviour is testable (and deterministic: the same inputs give the same states).
//
// Time: simulation time 0 is the capture time of the first tracking frame (or the
// start, with no tracking); capture times map onto simulation time from then on.
// Real kinematic bodies follow their tracked poses (TrackingDriver), but never into a
// static virtual body: against those they stop at the CCD's time-of-impact pose (the
// paper's application 1: the proxy of a tracked spoon stops at the teacup's rim), and
// the contact is reported.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/frame_order.hpp"
#include "simulator/dynamics/world.hpp"
#include "simulator/process/tracking_driver.hpp"

namespace arphys::sim {

struct TrackedObject {
  std::string object_id;
  bool lost = false;       // the tracker says it is not seen (status LOST)
  bool world_valid = true; // X_WO is meaningful
  geometry::Pose X_WO = geometry::Pose::Identity();
};

struct TrackingFrame {
  int64_t capture_utime = 0;  // microseconds since the epoch
  int64_t seq = 0;
  std::vector<TrackedObject> objects;
};

struct SpawnRequest {
  std::string sender;
  int64_t seq = 0;
  enum class Kind { kSpawn, kRemove, kReset, kPause, kResume } kind = Kind::kSpawn;
  std::string model;    // spawn: a virtual dynamic object of the scene
  std::string body_id;  // remove
  geometry::Pose X_WB = geometry::Pose::Identity();
  Eigen::Vector3d v_WB_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();
};

// A virtual body as a previous simulator left it (its last world state), to resume.
struct RecoveredBody {
  std::string body_id, model;
  geometry::Pose X_WB = geometry::Pose::Identity();
  Eigen::Vector3d v_WB_m_s = Eigen::Vector3d::Zero();  // velocity of the body origin, world frame
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();
};

struct RecoveryReport {
  int recovered = 0;
  std::vector<std::string> lost;  // "body id: why"
};

struct CoreOptions {
  TrackingPolicy policy = TrackingPolicy::kDelay;
  double stale_timeout_s = 0.5;      // no pose for this long: the object is held still
  DriverLimits driver_limits;       // how fast a tracked body may move where its tracking jumps
  double max_spawn_speed_m_s = 20;   // faster spawns are refused
  double max_spawn_distance_m = 10;  // spawns further from the world origin are refused
  double world_radius_m = 10;        // virtual bodies further than this (fallen off) are removed
  int threads = 1;                   // the world's worker threads (WorldOptions::threads)
};

// A contact the proxy of a real object made with a static virtual body.
struct ProxyContact {
  std::string body_a, body_b;
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero(), normal_W = Eigen::Vector3d::UnitZ();
  double time_of_impact_s = 0;
};

class SimulatorCore {
 public:
  SimulatorCore(config::SceneConfig scene, CoreOptions options);

  // Returns how many objects of the frame were used; every refusal is counted.
  int on_tracking(const TrackingFrame& frame);
  // Returns true when the command was carried out. Pause holds the world and the tracked
  // bodies where they are (frames while paused move nothing); resume goes on from there,
  // the time paused not simulated, and the next frame re-acquires the tracked bodies as
  // after a lost track (moving them to where they are seen at the driver's speed limit).
  bool on_command(const SpawnRequest& command);

  // Puts back the virtual dynamic bodies a previous run of the process left (after a
  // crash or restart): bodies the scene starts with continue from the saved state;
  // spawned ones are spawned again under their ids, within the same limits as a spawn
  // command. What cannot come back is listed with the reason. Tracked real bodies are put
  // back where they were (tracking moves them on from there); static ones are the scene's.
  RecoveryReport recover(const std::vector<RecoveredBody>& bodies);

  // Steps the world (fixed time step) up to simulation time t_s. Returns the steps taken.
  int advance_to(double t_s);
  // The simulation time a capture time maps to (after the first frame; else 0).
  double sim_time_of(int64_t capture_utime) const;
  // Gives up dropped_s of simulation time, for a live simulator that cannot keep up with
  // the camera: instead of falling ever further behind it (seconds of lag in the overlay),
  // it runs the virtual bodies slow for a moment, as a game engine's cap on substeps does.
  // Captures, and the tracked bodies' poses, map dropped_s earlier from now on: the next
  // step carries each tracked body through dropped_s more of its motion (no jump, but a
  // push that much faster for one step; give up small amounts). Not for replays: when it
  // drops depends on the machine's speed. Throws unless dropped_s > 0 and finite.
  void drop_time(double dropped_s);
  // Simulation time given up so far (drop_time), seconds.
  double dropped_time_s() const { return dropped_time_s_; }
  bool clock_started() const { return first_capture_utime_.has_value(); }

  double sim_time_s() const { return world_.time_s(); }
  double time_step_s() const { return scene_.time_step_s; }
  bool paused() const { return paused_; }
  const dynamics::World& world() const { return world_; }
  const config::SceneConfig& scene() const { return scene_; }
  const dynamics::StepReport& last_report() const { return last_report_; }
  const std::vector<ProxyContact>& proxy_contacts() const { return proxy_contacts_; }
  // Newest tracking frame used: capture utime and sequence (0 when none yet).
  int64_t newest_capture_utime() const { return newest_capture_utime_; }
  int64_t newest_seq() const { return newest_seq_; }
  // Refusals by reason ("out-of-order frame", "unknown object 'x'", ...).
  const std::map<std::string, int64_t>& rejections() const { return rejections_; }
  int64_t rejected_total() const;
  std::string last_rejection() const { return last_rejection_; }
  // Virtual bodies removed because they left the world (world_radius_m): how many, and
  // the last one's id (a count, not a list: a long run must not grow it).
  int64_t bodies_left_world() const { return bodies_left_world_; }
  const std::string& last_body_left_world() const { return last_body_left_world_; }
  // Objects whose track is lost or stale.
  std::vector<std::string> lost_objects() const;
  double added_latency_s(const std::string& object_id) const;

 private:
  void reject(const std::string& reason);
  // Adds a virtual dynamic instance of object, or returns why not (limits, overlap; a
  // resumed body may touch or overlap others as it did before the restart).
  std::string add_instance(const config::ObjectConfig& object, const std::string& id, const geometry::Pose& X_WB,
                           const Eigen::Vector3d& v_WB_m_s, const Eigen::Vector3d& w_WB_rad_s, bool resumed = false);
  void reset();
  void update_kinematic(double t0, double t1);
  // Maps captures by_s earlier from now on (the tracked bodies' poses and last sightings
  // with them); returns the shift as applied, in whole microseconds.
  double shift_clock(double by_s);

  config::SceneConfig scene_;
  CoreOptions options_;
  dynamics::World world_;
  std::map<std::string, TrackingDriver> drivers_;  // per tracked (kinematic, real) object
  std::map<std::string, double> last_seen_s_;
  std::map<std::string, int> spawn_counter_;
  std::map<std::string, int64_t> last_command_seq_;  // per sender
  std::optional<int64_t> first_capture_utime_;
  msg::FrameOrder frame_order_;
  int64_t newest_capture_utime_ = 0, newest_seq_ = 0;
  bool paused_ = false;
  dynamics::StepReport last_report_;
  std::vector<ProxyContact> proxy_contacts_;
  std::map<std::string, int64_t> rejections_;
  std::string last_rejection_;
  int64_t bodies_left_world_ = 0;
  std::string last_body_left_world_;
  double dropped_time_s_ = 0;
};

}  // namespace arphys::sim
