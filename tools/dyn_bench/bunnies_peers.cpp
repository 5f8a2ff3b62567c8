#include "tools/dyn_bench/bunnies_peers.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/scene/scene_world.hpp"
#include "tools/dyn_bench/bunny_peer.hpp"

namespace arphys::dyn_bench {
namespace {

using Clock = std::chrono::steady_clock;
using dynamics::RigidBody;

// Deepest overlap (metres, >= 0) of any two bodies at these poses, by arphys's manifolds.
double deepest_overlap_m(const std::vector<RigidBody>& bodies, const std::vector<geometry::Pose>& X_WB) {
  double deepest = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      if (!bodies[i].is_dynamic() && !bodies[j].is_dynamic()) continue;
      if ((X_WB[i].translation() - X_WB[j].translation()).norm() >
          bodies[i].bounding_radius_m() + bodies[j].bounding_radius_m())
        continue;
      for (const auto& p : collision::contact_manifold(bodies[i].shape, X_WB[i], bodies[j].shape, X_WB[j], 0.0))
        deepest = std::max(deepest, -p.distance_m);
    }
  return deepest;
}

struct Row {
  double ms_per_step = 0, simulated_s = 0, deepest_overlap_m = 0;
  bool diverged = false;  // stopped at simulated_s (BunnyPeer::diverged)
};

Row run_arphys(const config::SceneConfig& scene, double duration_s) {
  dynamics::World world = arphys::scene::build_world(scene);
  const std::vector<RigidBody> bodies = world.body_copies();  // their shapes (the scene adds and removes none)
  Row row;
  const long steps = std::lround(duration_s / scene.time_step_s);
  double wall = 0;
  for (long k = 0; k < steps; ++k) {
    const auto start = Clock::now();
    world.step(scene.time_step_s);
    wall += std::chrono::duration<double>(Clock::now() - start).count();
    std::vector<geometry::Pose> poses;
    for (const dynamics::BodyState& b : world.state().bodies) poses.push_back(b.X_WB);
    row.deepest_overlap_m = std::max(row.deepest_overlap_m, deepest_overlap_m(bodies, poses));
    row.simulated_s += scene.time_step_s;
    if (wall > 120) break;  // a scene that slows to a crawl is reported, not waited for
  }
  row.ms_per_step = 1e3 * wall * scene.time_step_s / row.simulated_s;
  return row;
}

// The scene's bodies for a peer, and the mesh the bunny's pieces were made from.
BunnyModel bunny_model(const config::SceneConfig& scene) {
  BunnyModel model;
  model.bodies = arphys::scene::build_world(scene).body_copies();
  model.gravity_m_s2 = scene.gravity_m_s2;
  for (const config::ObjectConfig& o : scene.objects)
    if (o.collision.type == config::ShapeType::kConvexSet && !o.collision.mesh_path.empty())
      model.bunny_mesh = geometry::load_mesh(o.collision.mesh_path, o.collision.scale);
  return model;
}

std::unique_ptr<BunnyPeer> make_peer(const std::string& engine, const BunnyModel& model, double dt_s) {
  if (engine == "bullet-compound") return make_bullet_bunnies(model, false);
  if (engine == "bullet-gimpact") return make_bullet_bunnies(model, true);
  if (engine == "mujoco") return make_mujoco_bunnies(model, dt_s);
  return make_ode_bunnies(model);
}

Row run_peer(const std::string& engine, const config::SceneConfig& scene, double duration_s) {
  const BunnyModel model = bunny_model(scene);
  const std::vector<RigidBody>& bodies = model.bodies;
  const std::unique_ptr<BunnyPeer> peer = make_peer(engine, model, scene.time_step_s);
  Row row;
  const long steps = std::lround(duration_s / scene.time_step_s);
  double wall = 0;
  std::vector<geometry::Pose> poses(bodies.size());
  for (long k = 0; k < steps; ++k) {
    const double t = k * scene.time_step_s;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].motion == dynamics::BodyMotion::kKinematic) {
        const geometry::Pose X = bodies[i].trajectory.pose_at(t + scene.time_step_s);
        peer->set_kinematic(static_cast<int>(i), X, bodies[i].trajectory.twist_at(t).v_WBo_m_s);
      }
    const auto start = Clock::now();
    peer->step(scene.time_step_s);
    wall += std::chrono::duration<double>(Clock::now() - start).count();
    if (peer->diverged()) {
      row.diverged = true;
      row.simulated_s += scene.time_step_s;
      break;
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) poses[i] = peer->pose(static_cast<int>(i));
    row.deepest_overlap_m = std::max(row.deepest_overlap_m, deepest_overlap_m(bodies, poses));
    row.simulated_s += scene.time_step_s;
    if (wall > 120) break;  // as for arphys
  }
  row.ms_per_step = 1e3 * wall * scene.time_step_s / std::max(row.simulated_s, scene.time_step_s);
  return row;
}

}  // namespace

void run_bunnies_peers(const std::string& configs_dir, double duration_s, std::ostream& csv) {
  std::printf("\n== bunnies against their peers (Bullet compound of the pieces and GImpact on the mesh, MuJoCo on the "
              "pieces, ODE trimesh): dt 10 ms, %.1f s, one run\n"
              "%-12s %-16s %10s %16s %18s\n",
              duration_s, "scene", "engine", "ms/step", "real-time factor", "deepest overlap mm");
  for (const std::string name : {"bunnies20", "bunnies100"}) {
    const auto scene = config::load_scene(configs_dir + "/scenes/" + name + ".yaml");
    for (const std::string engine : {"arphys", "bullet-compound", "bullet-gimpact", "mujoco", "ode-trimesh"}) {
      const Row row = engine == "arphys" ? run_arphys(scene, duration_s) : run_peer(engine, scene, duration_s);
      std::printf("%-12s %-16s %10.3f %16.2f %18.3f%s\n", name.c_str(), engine.c_str(), row.ms_per_step,
                  1e3 * scene.time_step_s / row.ms_per_step, 1e3 * row.deepest_overlap_m,
                  row.diverged ? ("   diverged at " + std::to_string(row.simulated_s) + " s: stopped").c_str() : "");
      std::fflush(stdout);
      csv << name << "," << engine << "," << row.ms_per_step << "," << 1e3 * scene.time_step_s / row.ms_per_step << ","
          << 1e3 * row.deepest_overlap_m << "," << row.simulated_s << "\n";
    }
  }
}

}  // namespace arphys::dyn_bench
