// The main job's load study (tools/eval/main_job_load.hpp): it must do to the simulator
// what the main job does, second by second: step it up to each frame's capture time (one
// simulated second a second) and throw in a bunny a second.
#include <gtest/gtest.h>

#include <cmath>

#include "configs/loader/camera_script.hpp"
#include "tools/eval/main_job_load.hpp"

namespace arphys::eval {
namespace {

const config::CameraScriptConfig& script() {
  static const config::CameraScriptConfig s =
      config::load_camera_script(config::default_config_dir() + "/synthetic/box_push.yaml");
  return s;
}

TEST(MainJobLoad, StepsEachSimulatedSecondAndThrowsInABunnyASecond) {
  const std::vector<LoadSecond> load = run_main_job_load(script(), 7, 3.0);
  ASSERT_EQ(load.size(), 3u);
  const int steps_per_second = static_cast<int>(std::lround(1.0 / script().scene.time_step_s));
  for (std::size_t s = 0; s < load.size(); ++s) {
    EXPECT_EQ(load[s].second, static_cast<int>(s));
    // A frame's steps may straddle a second's end: within one frame's worth (2 steps at 30 Hz).
    EXPECT_NEAR(load[s].steps, steps_per_second, 2) << "second " << s;
    EXPECT_TRUE(std::isfinite(load[s].ms_per_step) && load[s].ms_per_step > 0) << "second " << s;
    // 50 steps in 30 frames: the slowest frame holds at least the mean step.
    EXPECT_GE(load[s].max_frame_ms, load[s].ms_per_step) << "second " << s;
    EXPECT_EQ(load[s].bodies_left_world, 0);
  }
  // The scene starts with its own bunnies; one more arrives at the end of each second.
  EXPECT_EQ(load[1].virtual_bodies, load[0].virtual_bodies + 1);
  EXPECT_EQ(load[2].virtual_bodies, load[1].virtual_bodies + 1);
}

TEST(MainJobLoad, RefusesANonPositiveDuration) {
  EXPECT_THROW(run_main_job_load(script(), 7, 0.0), std::invalid_argument);
  EXPECT_THROW(run_main_job_load(script(), 7, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::eval
