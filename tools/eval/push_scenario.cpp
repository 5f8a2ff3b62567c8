#include "tools/eval/push_scenario.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include "simulator/scene/scene_world.hpp"
#include "simulator/process/tracking_driver.hpp"
#include "tracker/pose/constant_velocity_filter.hpp"

namespace arphys::eval {

const char* to_string(Drive drive) {
  switch (drive) {
    case Drive::kScrew: return "screw";
    case Drive::kScrewFiltered: return "screw+filter";
    case Drive::kTeleport: return "teleport";
  }
  return "?";
}

namespace {

constexpr double kPushStart_s = 0.6;  // the bunny has settled by then
constexpr double kPushFor_s = 1.8;

Eigen::Vector3d box_position(double t, double speed) {
  return {-0.3 + speed * std::clamp(t - kPushStart_s, 0.0, kPushFor_s), 0.0, 0.075};
}

Eigen::Matrix3d small_rotation(std::mt19937& rng, double sigma_rad) {
  std::normal_distribution<double> n(0, sigma_rad);
  const Eigen::Vector3d r(n(rng), n(rng), n(rng));
  return r.norm() > 0 ? Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

}  // namespace

PushOutcome run_push(const config::SceneConfig& scene_in, const PushScenario& s) {
  config::SceneConfig scene = scene_in;
  for (auto& o : scene.objects) {
    o.spawn_at_start.clear();
    if (o.id == "box") o.X_WO = geometry::translation_pose(box_position(0, s.push_speed_m_s));
  }
  const config::ObjectConfig* bunny_object = scene.find_object("bunny");
  if (!bunny_object || !scene.find_object("box")) throw std::invalid_argument("push scenario: the scene needs 'box' and 'bunny'");
  dynamics::World world = arphys::scene::build_world(scene);
  // A virtual object without spawns starts as one body at its pose: placed below instead
  // (removed before any index is taken: removal shifts the ones after it).
  if (world.find("bunny") >= 0) world.remove_body(world.find("bunny"));
  const int box = world.find("box");

  // The bunny upright (z-up), its lowest point 2 mm above the table, its back 5 cm ahead
  // of the box's front face.
  const geometry::Pose R_up = geometry::make_pose({0, 0, 0}, {0.7071067811865476, 0.7071067811865476, 0, 0});
  dynamics::RigidBody probe = arphys::scene::make_instance(*bunny_object, "bunny", R_up, {0, 0, 0}, {0, 0, 0});
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9);
  for (const auto& v : probe.shape.triangles()->mesh().vertices_m) lo = lo.cwiseMin(R_up * v);
  const Eigen::Vector3d start(-0.3 + 0.075 + 0.05 - lo.x(), 0.0, 0.002 - lo.z());
  geometry::Pose X_bunny = R_up;
  X_bunny.translation() = start;
  world.add_body(arphys::scene::make_instance(*bunny_object, "bunny", X_bunny, {0, 0, 0}, {0, 0, 0}));
  const int bunny = world.find("bunny");

  std::mt19937 rng(s.seed);
  std::normal_distribution<double> noise(0, 1);
  sim::TrackingDriver driver(sim::TrackingPolicy::kDelay, {}, 1.0 / s.frame_rate_hz);
  tracking::ConstantVelocityPoseFilter filter;
  const double dt = scene.time_step_s;
  const double frame_interval = 1.0 / s.frame_rate_hz;
  double next_frame = 0;
  const int flip_frame = s.flip_at_s < 0 ? -1 : static_cast<int>(std::lround(s.flip_at_s * s.frame_rate_hz));
  int frame = 0;
  PushOutcome out;
  double rest_z = std::nan("");
  const long steps = std::lround(s.duration_s / dt);
  const auto wall_start = std::chrono::steady_clock::now();
  for (long k = 0; k < steps; ++k) {
    const double t0 = k * dt, t1 = (k + 1) * dt;
    const geometry::Pose from = world.body_state(box).X_WB;
    // Frames captured up to t0 (a frame's pose is the truth at its capture time, noised).
    bool teleport_to_new = false;
    geometry::Pose newest = from;
    while (next_frame <= t0 + 1e-12) {
      const double tc = next_frame;
      const bool lost = tc >= s.lost_from_s && tc < s.lost_from_s + s.lost_for_s;
      geometry::Pose X = geometry::translation_pose(box_position(tc, s.push_speed_m_s));
      X.translation() += s.noise_position_m * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      X.linear() = small_rotation(rng, s.noise_rotation_deg * M_PI / 180) * X.linear();
      if (frame == flip_frame) {
        // The other IPPE solution: tilted about an axis in the image plane, same centre.
        X.linear() = Eigen::AngleAxisd(s.flip_angle_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() * X.linear();
      }
      if (lost) {
        driver.on_lost(t0);
      } else {
        if (s.drive == Drive::kScrewFiltered) X = filter.filter(X, tc);
        driver.on_pose(tc, X, t0);
        newest = X;
        teleport_to_new = true;
      }
      ++frame;
      next_frame = frame * frame_interval;
    }
    geometry::Pose to = from;
    if (s.drive == Drive::kTeleport) {
      // Jumps: no motion, no velocity. Placed, so the world sees the jump (its pairs are
      // tested for overlap, the sleepers it lands in wake); a pose set directly would pass
      // through a sleeping bunny unseen.
      if (teleport_to_new) world.place_body(box, newest);
      to = world.body_state(box).X_WB;
      dynamics::KinematicTrajectory held;
      held.add(t0, to);
      held.add(t1, to);
      world.set_trajectory(box, std::move(held));
    } else if (driver.has_pose()) {
      to = driver.trajectory().pose_at(t1);
      dynamics::KinematicTrajectory moved;
      moved.add(t0, from);
      moved.add(t1, to);
      world.set_trajectory(box, std::move(moved));
    }
    const dynamics::StepReport report = world.step(dt);
    const dynamics::BodyState& b = world.body_state(bunny);
    const Eigen::Vector3d com_W = dynamics::com_W(world.body_model(bunny), b);
    if (!b.X_WB.matrix().allFinite() || !b.v_WBcm_m_s.allFinite()) {
      out.non_finite = true;
      break;
    }
    out.max_overlap_mm = std::max(out.max_overlap_mm, 1e3 * report.max_penetration_m);
    // The centre of mass: the mesh origin of a turning bunny moves fast without the bunny going anywhere.
    if (t1 >= kPushStart_s - 0.05 && std::isnan(rest_z)) rest_z = com_W.z();
    if (!std::isnan(rest_z)) {
      out.max_rise_mm = std::max(out.max_rise_mm, 1e3 * (com_W.z() - rest_z));
      out.peak_speed_ratio = std::max(out.peak_speed_ratio, b.v_WBcm_m_s.norm() / s.push_speed_m_s);
    }
  }
  out.ms_per_step = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count() / steps;
  out.pushed_m = world.body_state(bunny).X_WB.translation().x() - start.x();

  return out;
}

}  // namespace arphys::eval
