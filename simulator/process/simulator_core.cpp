#include "simulator/process/simulator_core.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/scene/scene_world.hpp"

namespace arphys::sim {

SimulatorCore::SimulatorCore(config::SceneConfig scene, CoreOptions options)
    : scene_(std::move(scene)), options_(options) {
  reset();  // builds the world
}

void SimulatorCore::reset() {
  world_ = arphys::scene::build_world(scene_, options_.threads);
  drivers_.clear();
  last_seen_s_.clear();
  spawn_counter_.clear();
  for (const auto& object : scene_.objects) {
    if (object.role == config::Role::kReal && object.motion == config::Motion::kKinematic)
      drivers_.emplace(object.id, TrackingDriver(options_.policy, options_.driver_limits));
    spawn_counter_[object.id] = static_cast<int>(object.spawn_at_start.size());
  }
  proxy_contacts_.clear();
  first_capture_utime_.reset();
}

void SimulatorCore::reject(const std::string& reason) {
  // Reasons quote what a message said (an object id, a sender): hostile traffic must not
  // grow the table without bound, so past kMaxReasons distinct ones they share a row.
  constexpr std::size_t kMaxReasons = 64;
  if (rejections_.size() < kMaxReasons || rejections_.count(reason)) {
    ++rejections_[reason];
  } else {
    ++rejections_["other reasons (table full)"];
  }
  last_rejection_ = reason;
}

int64_t SimulatorCore::rejected_total() const {
  int64_t total = 0;
  for (const auto& [reason, count] : rejections_) total += count;
  return total;
}

double SimulatorCore::sim_time_of(int64_t capture_utime) const {
  if (!first_capture_utime_) return world_.time_s();
  return static_cast<double>(capture_utime - *first_capture_utime_) * 1e-6;
}

void SimulatorCore::drop_time(double dropped_s) {
  if (!(dropped_s > 0) || !std::isfinite(dropped_s))
    throw std::invalid_argument("SimulatorCore::drop_time: dropped_s must be positive and finite, got " +
                                std::to_string(dropped_s));
  // The tracked bodies' poses move with their captures, so the next step carries each
  // body through dropped_s more of its motion: its speed that step is (1 + dropped_s / dt)
  // times its own, which is why the caller gives up small amounts often, not a backlog at once.
  dropped_time_s_ += shift_clock(dropped_s);
}

double SimulatorCore::shift_clock(double by_s) {
  const int64_t by_us = std::llround(by_s * 1e6);
  const double by = static_cast<double>(by_us) * 1e-6;  // as the capture mapping moves
  if (first_capture_utime_) *first_capture_utime_ += by_us;
  for (auto& [id, seen_s] : last_seen_s_) seen_s -= by;
  for (auto& [id, driver] : drivers_) driver.shift_time(-by);
  return by;
}

int SimulatorCore::on_tracking(const TrackingFrame& frame) {
  // One stream of tracking frames, whichever tracker sends it (trackers swap live).
  const auto verdict = frame_order_.check("", frame.seq, frame.capture_utime);
  if (verdict != msg::FrameOrder::Verdict::kNew) {
    reject(std::string(msg::to_string(verdict)) + " tracking frame");
    return 0;
  }
  if (!first_capture_utime_) {
    // Simulation time now corresponds to this capture.
    first_capture_utime_ = frame.capture_utime - static_cast<int64_t>(std::llround(world_.time_s() * 1e6));
  }
  newest_capture_utime_ = frame.capture_utime;
  newest_seq_ = frame.seq;
  if (paused_) return 0;  // (the tracked bodies are held: see on_command)
  const double t = sim_time_of(frame.capture_utime);
  int used = 0;
  for (const TrackedObject& object : frame.objects) {
    auto driver = drivers_.find(object.object_id);
    if (driver == drivers_.end()) {
      // A static real object (the table) fixes the world frame: the tracker reports it,
      // the simulator has nothing to move.
      const config::ObjectConfig* config = scene_.find_object(object.object_id);
      if (config && config->role == config::Role::kReal && config->motion == config::Motion::kStatic) continue;
      reject(scene_.find_object(object.object_id) ? "object '" + object.object_id + "' is not a tracked kinematic object"
                                                  : "unknown object '" + object.object_id + "'");
      continue;
    }
    if (object.lost) {
      driver->second.on_lost(std::max(t, world_.time_s()));
      continue;
    }
    if (!object.world_valid) {
      reject("pose of '" + object.object_id + "' not in the world frame");
      continue;
    }
    if (!object.X_WO.matrix().allFinite()) {
      reject("non-finite pose of '" + object.object_id + "'");
      continue;
    }
    driver->second.on_pose(t, object.X_WO, world_.time_s());
    last_seen_s_[object.object_id] = t;
    ++used;
  }
  return used;
}

bool SimulatorCore::on_command(const SpawnRequest& command) {
  auto last = last_command_seq_.find(command.sender);
  if (last != last_command_seq_.end() && command.seq <= last->second) {
    reject("repeated command from '" + command.sender + "'");
    return false;
  }
  // One entry per sender; random sender names must not grow it without bound (a sender
  // forgotten this way can repeat its last command once).
  constexpr std::size_t kMaxSenders = 256;
  if (last == last_command_seq_.end() && last_command_seq_.size() >= kMaxSenders) last_command_seq_.clear();
  last_command_seq_[command.sender] = command.seq;
  switch (command.kind) {
    case SpawnRequest::Kind::kPause:
      if (!paused_) {
        // The tracked bodies stop where they are, as on a lost track: frames that come
        // while paused move nothing, and the first after the resume re-acquires them.
        for (auto& [id, driver] : drivers_) driver.on_lost(world_.time_s());
        paused_ = true;
      }
      return true;
    case SpawnRequest::Kind::kResume:
      if (paused_) {
        paused_ = false;
        // The time paused is not simulated: the captures map that much earlier from now
        // on, so the world goes on from where it stopped instead of running through it.
        const double paused_s = clock_started() ? sim_time_of(newest_capture_utime_) - world_.time_s() : 0.0;
        if (paused_s > 0) shift_clock(paused_s);
      }
      return true;
    case SpawnRequest::Kind::kReset: reset(); return true;
    case SpawnRequest::Kind::kRemove: {
      const int index = world_.find(command.body_id);
      if (index < 0 || world_.body_model(index).real) {
        reject("cannot remove '" + command.body_id + "' (no such virtual body)");
        return false;
      }
      world_.remove_body(index);
      return true;
    }
    case SpawnRequest::Kind::kSpawn: break;
  }
  const config::ObjectConfig* object = scene_.find_object(command.model);
  if (!object || object->role != config::Role::kVirtual || object->motion != config::Motion::kDynamic) {
    reject("spawn of '" + command.model + "': not a virtual dynamic object of the scene");
    return false;
  }
  const std::string id = object->id + "#" + std::to_string(spawn_counter_[object->id]);
  const std::string refusal = add_instance(*object, id, command.X_WB, command.v_WB_m_s, command.w_WB_rad_s);
  if (!refusal.empty()) {
    reject("spawn of '" + command.model + "': " + refusal);
    return false;
  }
  return true;
}

std::string SimulatorCore::add_instance(const config::ObjectConfig& object, const std::string& id,
                                        const geometry::Pose& X_WB, const Eigen::Vector3d& v_WB_m_s,
                                        const Eigen::Vector3d& w_WB_rad_s, bool resumed) {
  int live = 0;
  for (const auto& body : world_.model().bodies) live += body.model == object.id;
  if (live >= object.max_instances) {
    return std::to_string(live) + " live, the limit is " + std::to_string(object.max_instances);
  }
  if (!X_WB.matrix().allFinite() || !v_WB_m_s.allFinite() || !w_WB_rad_s.allFinite()) {
    return "non-finite pose or velocity";
  }
  if (X_WB.translation().norm() > options_.max_spawn_distance_m) {
    return "further than " + std::to_string(options_.max_spawn_distance_m) + " m from the world origin";
  }
  if (v_WB_m_s.norm() > options_.max_spawn_speed_m_s) {
    return "faster than " + std::to_string(options_.max_spawn_speed_m_s) + " m/s";
  }
  if (world_.find(id) >= 0) return "a body '" + id + "' exists";
  dynamics::RigidBody body = arphys::scene::make_instance(object, id, X_WB, v_WB_m_s, w_WB_rad_s);
  // A body spawned into another one cannot be resolved physically (both are pushed
  // apart at the depenetration speed, and a stack of them buries the solver): refused.
  // A resumed body was where it is in the world the killed simulator ran, touching its
  // neighbours (meshes at rest intersect by micrometres, more in a squeezed pile): it
  // comes back as it was, unless another body is at its very pose (a duplicate, not a
  // state the world can have been in). Refusing every overlap lost a touching bunny in 6
  // of 14 runs of the process-restart test.
  const auto at_its_pose = [&](const geometry::Pose& X_WO) {
    return (X_WO.translation() - X_WB.translation()).norm() < 1e-3 &&
           Eigen::AngleAxisd(X_WO.linear().transpose() * X_WB.linear()).angle() < 1e-2;
  };
  const auto overlaps = [&](const dynamics::BodyModel& other, const geometry::Pose& X_WO) {
    if (other.shape.type() != collision::Shape::Type::kPlane &&
        (X_WO.translation() - body.X_WB.translation()).norm() > other.bounding_radius_m() + body.bounding_radius_m()) {
      return false;
    }
    if (body.shape.triangles() && other.shape.triangles())
      return collision::intersects(*body.shape.triangles(), body.X_WB, *other.shape.triangles(), X_WO);
    // Planes and spheres report signed distances: negative is a penetration.
    for (const auto& point : collision::contact_manifold(body.shape, body.X_WB, other.shape, X_WO, 1e-4))
      if (point.distance_m < 0.0) return true;
    return false;
  };
  for (int i = 0; i < world_.body_count(); ++i) {
    const dynamics::BodyModel& other = world_.body_model(i);
    const geometry::Pose& X_WO = world_.body_state(i).X_WB;
    if (resumed && other.shape.type() != collision::Shape::Type::kPlane && at_its_pose(X_WO))
      return "would overlap '" + other.id + "' (at its pose)";
    if (!resumed && overlaps(other, X_WO)) return "would overlap '" + other.id + "'";
  }
  // Generated ids continue after the highest one in use ("bunny#7" -> next "bunny#8").
  const std::size_t hash = id.rfind('#');
  int number = -1;
  if (hash != std::string::npos && id.compare(0, hash, object.id) == 0) {
    try {
      number = std::stoi(id.substr(hash + 1));
    } catch (const std::exception&) {
      number = -1;
    }
  }
  spawn_counter_[object.id] = std::max(spawn_counter_[object.id], number + 1);
  world_.add_body(std::move(body));
  return "";
}

RecoveryReport SimulatorCore::recover(const std::vector<RecoveredBody>& bodies) {
  RecoveryReport report;
  for (const RecoveredBody& saved : bodies) {
    const config::ObjectConfig* object = scene_.find_object(saved.model);
    if (!object) {
      report.lost.push_back(saved.body_id + ": model '" + saved.model + "' is not in the scene");
      continue;
    }
    if (object->role == config::Role::kReal && object->motion == config::Motion::kKinematic) {
      // A tracked body goes back where it was: the first tracked pose after the restart
      // then moves it on by a screw motion. Left at its scene pose, it jumped to the
      // tracked pose into the bunnies it had been pushing and shoved them 0.2-0.3 m.
      const int index = world_.find(saved.body_id);
      const auto driver = drivers_.find(saved.body_id);
      if (index >= 0 && driver != drivers_.end() && saved.X_WB.matrix().allFinite()) {
        world_.place_body(index, saved.X_WB);
        driver->second.hold_at(world_.time_s(), saved.X_WB);
      }
      continue;
    }
    if (object->role != config::Role::kVirtual || object->motion != config::Motion::kDynamic) continue;  // static: the scene's
    const int index = world_.find(saved.body_id);
    if (index >= 0) {  // a body the scene starts with: continue it where it was
      if (!saved.X_WB.matrix().allFinite() || !saved.v_WB_m_s.allFinite() || !saved.w_WB_rad_s.allFinite()) {
        report.lost.push_back(saved.body_id + ": non-finite state");
        continue;
      }
      world_.place_body(index, saved.X_WB);
      world_.set_origin_velocity(index, saved.v_WB_m_s, saved.w_WB_rad_s);
      ++report.recovered;
      continue;
    }
    const std::string refusal =
        add_instance(*object, saved.body_id, saved.X_WB, saved.v_WB_m_s, saved.w_WB_rad_s, /*resumed=*/true);
    if (refusal.empty()) {
      ++report.recovered;
    } else {
      report.lost.push_back(saved.body_id + ": " + refusal);
    }
  }
  return report;
}

// Each tracked body moves, over [t0, t1], from where it is to where its tracking says,
// unless that motion meets a static virtual body: then it stops at the time of impact.
void SimulatorCore::update_kinematic(double t0, double t1) {
  proxy_contacts_.clear();
  for (auto& [id, driver] : drivers_) {
    const int index = world_.find(id);
    if (index < 0 || !driver.has_pose()) continue;
    auto seen = last_seen_s_.find(id);
    if (seen != last_seen_s_.end() && t0 - seen->second > options_.stale_timeout_s) driver.on_lost(t0);
    const dynamics::BodyModel& body = world_.body_model(index);
    const geometry::Pose from = world_.body_state(index).X_WB;
    geometry::Pose to = driver.trajectory().pose_at(t1);
    const geometry::ScrewMotion motion(from, to);
    double earliest = 1.0;
    for (int o = 0; o < world_.body_count(); ++o) {
      const dynamics::BodyModel& other = world_.body_model(o);
      if (other.real || other.motion != dynamics::BodyMotion::kStatic) continue;
      const geometry::Pose& X_WO = world_.body_state(o).X_WB;
      // (The world's CCD settings: its time tolerance and work budgets, whose answers are
      // never late. A proxy stopped at the cup starts every later query touching it.)
      const auto r = collision::time_of_impact(body.shape, motion, other.shape, geometry::ScrewMotion(X_WO, X_WO),
                                               world_.options().ccd);
      if (!r.collides || r.features.kind == collision::FeaturePair::kOverlapAtStart) continue;
      if (r.time_of_impact < earliest) {
        earliest = r.time_of_impact;
        proxy_contacts_.clear();
        proxy_contacts_.push_back({id, other.id, r.point_W, r.normal_W, t0 + earliest * (t1 - t0)});
      }
    }
    if (earliest < 1.0) to = motion.pose_at(earliest);
    dynamics::KinematicTrajectory trajectory;
    trajectory.add(t0, from);
    if (t1 > t0) trajectory.add(t1, to);
    world_.set_trajectory(index, std::move(trajectory));
  }
}

int SimulatorCore::advance_to(double t_s) {
  int steps = 0;
  const double dt = scene_.time_step_s;
  while (!paused_ && world_.time_s() + dt <= t_s + 1e-12) {
    update_kinematic(world_.time_s(), world_.time_s() + dt);
    last_report_ = world_.step(dt);
    ++steps;
    // A virtual body that fell off the table would fall forever and hold one of the
    // scene's instances: past the world radius it is removed, and said so.
    for (int i = world_.body_count() - 1; i >= 0; --i) {
      const dynamics::BodyModel& body = world_.body_model(i);
      if (!body.real && body.is_dynamic() &&
          !(world_.body_state(i).X_WB.translation().norm() <= options_.world_radius_m)) {
        ++bodies_left_world_;
        last_body_left_world_ = body.id;
        world_.remove_body(i);
      }
    }
  }
  return steps;
}

std::vector<std::string> SimulatorCore::lost_objects() const {
  std::vector<std::string> lost;
  for (const auto& [id, driver] : drivers_) {
    auto seen = last_seen_s_.find(id);
    if (seen == last_seen_s_.end() || world_.time_s() - seen->second > options_.stale_timeout_s) lost.push_back(id);
  }
  return lost;
}

double SimulatorCore::added_latency_s(const std::string& object_id) const {
  auto it = drivers_.find(object_id);
  return it == drivers_.end() ? 0.0 : it->second.added_latency_s();
}

}  // namespace arphys::sim
