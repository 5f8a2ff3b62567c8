#include "simulator/geometry/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace arphys::geometry {
namespace {

const std::string kModels = std::string(ARPHYS_SOURCE_DIR) + "/configs/models/";

TEST(TriangleMesh, LoadsObjAsIsWithScale) {
  const TriangleMesh mesh = load_mesh(kModels + "stanford-bunny-5k.obj");
  EXPECT_EQ(mesh.num_triangles(), 5000u);
  EXPECT_EQ(mesh.num_vertices(), 2514u);
  // Bounding box of the published file (no recentring).
  EXPECT_NEAR(mesh.bounds().min().y(), 0.0332, 1e-4);
  EXPECT_NEAR(mesh.bounds().sizes().x(), 0.1561, 1e-4);
  const TriangleMesh scaled = load_mesh(kModels + "stanford-bunny-5k.obj", Eigen::Vector3d::Constant(2.0));
  EXPECT_NEAR(scaled.bounds().sizes().x(), 2 * 0.1561, 2e-4);
}

TEST(TriangleMesh, LoadsBinaryPly) {
  const TriangleMesh mesh = load_mesh(kModels + "stanford-bunny-70k.ply");
  EXPECT_EQ(mesh.num_triangles(), 69451u);
  // The scan repeats some vertex positions; assimp joins identical ones (35,947 in the file).
  EXPECT_EQ(mesh.num_vertices(), 34834u);
  EXPECT_NEAR(mesh.bounds().sizes().x(), 0.1557, 1e-4);
}

TEST(TriangleMesh, MissingFileNamesThePath) {
  try {
    load_mesh("/nonexistent/dir/teapot.obj");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/teapot.obj"), std::string::npos) << e.what();
  }
}

TEST(TriangleMesh, GarbageFileIsAnErrorNotACrash) {
  const std::string path = ::testing::TempDir() + "garbage.obj";
  std::ofstream(path) << "this is not a mesh\n\x01\x02\x03";
  EXPECT_THROW(load_mesh(path), std::runtime_error);
}

TEST(TriangleMesh, TopologyOfBoxAndOpenMeshes) {
  TriangleMesh box = make_box_mesh({1, 2, 3});
  EXPECT_TRUE(mesh_topology(box).closed());
  box.triangles.pop_back();  // open one face: 2 boundary edges of the removed triangle + the diagonal
  EXPECT_EQ(mesh_topology(box).boundary_edges, 3u);
  EXPECT_EQ(cap_boundary_loops(box), 1u);
  EXPECT_TRUE(mesh_topology(box).closed());
}

TEST(TriangleMesh, CapsTheBunnysHoles) {
  TriangleMesh bunny = load_mesh(kModels + "stanford-bunny-5k.obj");
  EXPECT_EQ(mesh_topology(bunny).boundary_edges, 32u);
  const std::size_t loops = cap_boundary_loops(bunny);
  EXPECT_GE(loops, 1u);
  EXPECT_TRUE(mesh_topology(bunny).closed());
}

}  // namespace
}  // namespace arphys::geometry
