#pragma once
// What the main job throws into its scene, one a second (arphys-launch): the scene's first
// virtual dynamic model, from the table's front edge towards its middle, its place and
// sideways speed spread by a seeded generator. The evaluation's main-job-load study
// (tools/eval/main_job_load.hpp) throws the same, so that it loads the simulator as the
// job does.
#include <random>

#include <Eigen/Core>

#include "configs/loader/scene_config.hpp"
#include "simulator/geometry/pose.hpp"

namespace arphys::launch {

struct Throw {
  geometry::Pose X_WB;       // body in the world at the spawn
  Eigen::Vector3d v_WB_m_s;  // velocity of the body origin, world frame
};

class MainJobThrows {
 public:
  static constexpr unsigned kLauncherSeed = 7;
  explicit MainJobThrows(unsigned seed = kLauncherSeed) : rng_(seed) {}

  Throw next() {
    Throw t;
    // (Two draws in this order: the place across the table, then the sideways speed.)
    const double across_m = spread_m_(rng_);
    t.X_WB = geometry::make_pose({across_m, -0.25, 0.25}, {0.7071067811865476, 0.7071067811865476, 0, 0});
    t.v_WB_m_s = {spread_m_(rng_), 0.3, 0.0};
    return t;
  }

 private:
  std::mt19937 rng_;
  std::uniform_real_distribution<double> spread_m_{-0.15, 0.15};  // metres, and metres per second
};

// The scene's first virtual dynamic model (what a user throws in), or nullptr.
inline const config::ObjectConfig* thrown_model(const config::SceneConfig& scene) {
  for (const auto& object : scene.objects)
    if (object.role == config::Role::kVirtual && object.motion == config::Motion::kDynamic) return &object;
  return nullptr;
}

}  // namespace arphys::launch
