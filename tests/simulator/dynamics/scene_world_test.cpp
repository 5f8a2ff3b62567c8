// Bodies built from scene files: the bunny of application 2 on its table.
#include "simulator/dynamics/scene_world.hpp"

#include <gtest/gtest.h>

#include "configs/loader/scene_config.hpp"

namespace arphys::dynamics {
namespace {

const std::string kScenes = std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/";

// Lowest point of a body's mesh in the world, metres.
double lowest_z(const RigidBody& body) {
  double lowest = 1e9;
  for (const auto& v : body.shape.triangles()->mesh().vertices_m) lowest = std::min(lowest, (body.X_WB * v).z());
  return lowest;
}

// The scanned bunny has holes in its base. Dropped upright from a few millimetres it
// used to find no resting contact on its open mesh's vertices, sink in and fall through
// the table (from 2, 5 and 10 mm; not from 1 or 3). Fixed in the contact manifold
// (DiscreteQuery.OpenSurfaceVerticesRestingOnASolidAreContacts).
TEST(SceneWorld, UprightBunnyDroppedFromLowHeightsRestsOnTheTable) {
  config::SceneConfig scene = config::load_scene(kScenes + "bunny_box_table.yaml");
  for (auto& o : scene.objects) o.spawn_at_start.clear();
  const config::ObjectConfig* bunny = scene.find_object("bunny");
  ASSERT_NE(bunny, nullptr);
  for (double gap_m : {0.0005, 0.002, 0.005, 0.01, 0.02}) {
    World world = build_world(scene);
    world.remove_body(world.find("bunny"));
    geometry::Pose X = geometry::make_pose({0, 0, 0}, {0.7071067811865476, 0.7071067811865476, 0, 0});
    RigidBody body = make_instance(*bunny, "b", X, {0, 0, 0}, {0, 0, 0});
    X.translation().z() = gap_m - lowest_z(body);
    body.X_WB = X;
    const int index = world.add_body(std::move(body));
    for (int k = 0; k < 100; ++k) world.step(0.01);
    EXPECT_GT(lowest_z(world.bodies()[index]), -1e-5) << "dropped from " << gap_m << " m";
    EXPECT_LT(lowest_z(world.bodies()[index]), 1e-3) << "dropped from " << gap_m << " m";
  }
}

}  // namespace
}  // namespace arphys::dynamics
