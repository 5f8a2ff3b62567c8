// decimate-quadric, run as a real process on the bundled bunny, and the collision mesh
// the bunny scenes ship that it made (configs/models/README.md).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <tuple>

#include "simulator/geometry/mass_properties.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace {

const std::string kModels = std::string(ARPHYS_SOURCE_DIR) + "/configs/models/";
const std::string kTool = std::string(ARPHYS_BINARY_DIR) + "/tools/models/decimate-quadric";

int run(const std::string& arguments) { return WEXITSTATUS(std::system((kTool + " " + arguments).c_str())); }

TEST(DecimateQuadric, KeepsTheSurfaceManifoldAndItsVerticesTheInputs) {
  const auto out = std::filesystem::path(::testing::TempDir()) / "bunny-1200.obj";
  ASSERT_EQ(run(kModels + "stanford-bunny-5k.obj " + out.string() + " --triangles 1200 > /dev/null"), 0);
  using arphys::geometry::load_mesh;
  const auto input = load_mesh(kModels + "stanford-bunny-5k.obj");
  const auto result = load_mesh(out.string());
  EXPECT_GE(result.num_triangles(), 1100u);
  EXPECT_LE(result.num_triangles(), 1200u);
  // Edge collapse keeps the topology: no non-manifold edge (vertex clustering made 84),
  // no more boundary than the scan's holes.
  const auto topology = arphys::geometry::mesh_topology(result);
  EXPECT_EQ(topology.non_manifold_edges, 0u);
  EXPECT_LE(topology.boundary_edges, arphys::geometry::mesh_topology(input).boundary_edges);
  // No new positions: every vertex is one of the input's (as written, to 9 digits).
  std::set<std::tuple<long, long, long>> inputs;
  const auto key = [](const Eigen::Vector3d& v) {
    return std::make_tuple(std::lround(v.x() * 1e7), std::lround(v.y() * 1e7), std::lround(v.z() * 1e7));
  };
  for (const auto& v : input.vertices_m) inputs.insert(key(v));
  for (const auto& v : result.vertices_m) EXPECT_TRUE(inputs.count(key(v))) << v.transpose();
}

TEST(DecimateQuadric, AMissingInputOrNoTrianglesIsNamedAndFails) {
  const auto err = std::filesystem::path(::testing::TempDir()) / "decimate_err.txt";
  const auto message = [&] {
    std::ifstream in(err);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_NE(run("/nonexistent/bunny.obj /dev/null 2> " + err.string()), 0);
  EXPECT_NE(message().find("/nonexistent/bunny.obj"), std::string::npos) << message();
  EXPECT_NE(run(kModels + "stanford-bunny-5k.obj /dev/null --triangles 0 2> " + err.string()), 0);
  EXPECT_NE(message().find("--triangles"), std::string::npos) << message();
}

TEST(DecimateQuadric, TheShippedCollisionBunnyIsASolidOnceCapped) {
  auto mesh = arphys::geometry::load_mesh(kModels + "stanford-bunny-1k-quadric.obj");
  EXPECT_EQ(mesh.num_triangles(), 1200u);
  EXPECT_EQ(arphys::geometry::mesh_topology(mesh).non_manifold_edges, 0u);
  arphys::geometry::cap_boundary_loops(mesh);
  ASSERT_TRUE(arphys::geometry::mesh_topology(mesh).closed());
  // Its volume within 2 % of the 5k bunny's (the decimation keeps the shape).
  auto fine = arphys::geometry::load_mesh(kModels + "stanford-bunny-5k.obj");
  arphys::geometry::cap_boundary_loops(fine);
  const double coarse_kg = arphys::geometry::mesh_mass_properties(mesh, 1000.0).mass_kg;
  const double fine_kg = arphys::geometry::mesh_mass_properties(fine, 1000.0).mass_kg;
  EXPECT_NEAR(coarse_kg / fine_kg, 1.0, 0.02);
}

}  // namespace
