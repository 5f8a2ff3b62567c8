// The step's worker threads: every index once, errors carried back, and a World that
// steps to the same bits on any number of threads.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "simulator/scene/scene_world.hpp"
#include "simulator/dynamics/worker_pool.hpp"

namespace arphys::dynamics {
namespace {

TEST(WorkerPool, RefusesAThreadCountOutOfRangeNamingIt) {
  try {
    WorkerPool pool(0);
    FAIL() << "0 threads accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("threads is 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(WorkerPool(257), std::invalid_argument);
  WorldOptions options;
  options.threads = -2;
  EXPECT_THROW(World{options}, std::invalid_argument);
}

TEST(WorkerPool, CallsEveryIndexOnceAndRethrows) {
  for (int threads : {1, 4}) {
    const WorkerPool pool(threads);
    std::vector<std::atomic<int>> calls(5000);
    pool.for_each(static_cast<int>(calls.size()), [&](int k) { calls[k].fetch_add(1); });
    for (std::size_t k = 0; k < calls.size(); ++k) ASSERT_EQ(calls[k].load(), 1) << "index " << k << ", " << threads << " threads";
    EXPECT_THROW(pool.for_each(100, [](int k) { if (k == 37) throw std::runtime_error("index 37"); }), std::runtime_error);
    pool.for_each(0, [](int) { FAIL() << "called for an empty range"; });
  }
}

// The paper's bunnies falling into a pile on the table, pushed by the tracked box: the
// same poses and velocities to the last bit whether the step's pairs run on 1 or 3 threads.
TEST(WorkerPool, AWorldStepsToTheSameBitsOnAnyNumberOfThreads) {
  const config::SceneConfig scene = config::load_scene(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunnies20.yaml");
  World one = arphys::scene::build_world(scene, 1);
  World three = arphys::scene::build_world(scene, 3);
  std::size_t most_contacts = 0;
  for (int step = 0; step < 80; ++step) {
    one.step(0.01);
    three.step(0.01);
    most_contacts = std::max(most_contacts, one.contacts().size());
    ASSERT_EQ(one.contacts().size(), three.contacts().size()) << "step " << step;
    for (int i = 0; i < one.body_count(); ++i) {
      const RigidBody& a = one.body_copy(i);
      const RigidBody& b = three.body_copy(i);
      ASSERT_TRUE(a.X_WB.matrix() == b.X_WB.matrix() && a.v_WBcm_m_s == b.v_WBcm_m_s && a.w_WB_rad_s == b.w_WB_rad_s)
          << a.id << " differs at step " << step;
    }
  }
  std::printf("most contacts: %zu\n", most_contacts);
  EXPECT_GT(most_contacts, 40u);  // the pile formed: its pairs were the threads' work
}

}  // namespace
}  // namespace arphys::dynamics
