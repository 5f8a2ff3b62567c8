// The paper's bunny scene as shipped (configs/scenes/bunnies20.yaml), stepped as the
// simulator steps it: a scene-level regression figure for what a user sees.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "simulator/dynamics/scene_world.hpp"

namespace arphys::dynamics {
namespace {

// A bounce chained within a step (a bunny struck, striking the table) cut the step where
// a bunny resting on the table crossed it at once: a cut of nothing, then the same again,
// and the whole group's step ended there (it waited). Its poses and velocities kept, the
// next step repeated it: from step 194 every one of the 20 bunnies stood still, step
// after step (31 frozen steps in a row by step 230).
TEST(BunnyScene, TwentyBunniesAsShippedNeverFreezeForLong) {
  const config::SceneConfig scene =
      config::load_scene(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunnies20.yaml");
  World world = build_world(scene);
  int frozen_in_a_row = 0, longest = 0;
  for (int step = 0; step < 230; ++step) {
    std::vector<geometry::Pose> before;
    for (const RigidBody& body : world.bodies()) before.push_back(body.X_WB);
    world.step(scene.time_step_s);
    bool moved = false;
    for (std::size_t i = 0; i < before.size(); ++i)
      moved |= world.bodies()[i].is_dynamic() && world.bodies()[i].X_WB.matrix() != before[i].matrix();
    frozen_in_a_row = moved ? 0 : frozen_in_a_row + 1;
    longest = std::max(longest, frozen_in_a_row);
  }
  EXPECT_LE(longest, 20);
}

}  // namespace
}  // namespace arphys::dynamics
