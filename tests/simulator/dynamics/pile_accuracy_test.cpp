// Scene 6 of issue 4 at its hardest: 1000 boxes dropped on a frictionless plane
// (configs/scenes/drop1000.yaml), over the 2 s the anchor timed its peers on. The issue's
// accuracy bound is that no pair ends a step more than 1e-5 m inside another, which no
// peer keeps (quickstep and Bullet: 3.7 mm). Slow (minutes): label `slow`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/scene/scene_world.hpp"

namespace arphys::dynamics {
namespace {

// The deepest overlap of any two bodies at their current poses (0: none).
double deepest_overlap_m(const World& world) {
  const auto& bodies = world.body_copies();
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const RigidBody& body : bodies) {
    if (body.shape.type() == collision::Shape::Type::kPlane) {
      boxes.emplace_back(Eigen::Vector3d::Constant(-1e9), Eigen::Vector3d(1e9, 1e9, 1e-3));
      continue;
    }
    const double r = body.bounding_radius_m() + 1e-3;
    boxes.emplace_back(body.X_WB.translation().array() - r, body.X_WB.translation().array() + r);
  }
  double deepest = 0;
  for (const auto& [i, j] : collision::overlapping_pairs(boxes))
    for (const auto& point : collision::contact_manifold(bodies[i].shape, bodies[i].X_WB, bodies[j].shape, bodies[j].X_WB, 0.0))
      deepest = std::max(deepest, -point.distance_m);
  return deepest;
}

// Every step of the frictionless pile ends within the bound, and no cut inside a
// step leaves a pair deeper than the rest of the step undoes (unswept_clear_fraction:
// without it, pairs left unswept were caught 124 um deep at cuts; with them unswept up to
// 4 mm, one caught 1.4 mm deep ended step 1393 522 um deep).
TEST(PileAccuracy, EveryStepOfTheFrictionless1000BoxPileEndsWithin10Micrometres) {
  World world = arphys::scene::build_world(config::load_scene(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/drop1000.yaml"));
  const double dt_s = 1e-3;
  const double undone_in_a_step_m = 0.5 * world.options().max_depenetration_speed_m_s * dt_s;
  double deepest = 0, deepest_at_cuts = 0;
  int deepest_step = -1;
  for (int step = 0; step < 2000; ++step) {
    const StepReport report = world.step(dt_s);
    deepest_at_cuts = std::max(deepest_at_cuts, report.max_penetration_m);
    ASSERT_LE(report.max_penetration_m, undone_in_a_step_m) << "step " << step;
    const double depth = deepest_overlap_m(world);
    if (depth > deepest) {
      deepest = depth;
      deepest_step = step;
    }
    if (step % 200 == 199) {
      std::printf("step %d: deepest step end so far %.2f um (step %d), at cuts %.1f um\n", step + 1, deepest * 1e6,
                  deepest_step, deepest_at_cuts * 1e6);
      std::fflush(stdout);  // a progress line for minutes of stepping
    }
    ASSERT_LE(depth, 1e-5) << "step " << step;
  }
}

}  // namespace
}  // namespace arphys::dynamics
