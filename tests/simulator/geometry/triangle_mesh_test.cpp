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

TEST(TriangleMesh, SavedObjLoadsBackTheSameTriangles) {
  TriangleMesh mesh = make_box_mesh({1.2, 0.8, 0.04});
  mesh.vertices_m[0].z() = 0.123456789;  // more digits than the default six keep (0.123457)
  const std::string path = ::testing::TempDir() + "/saved_box.obj";
  save_obj(mesh, path);
  const TriangleMesh back = load_mesh(path);
  ASSERT_EQ(back.num_triangles(), mesh.num_triangles());
  // Corner by corner, to single precision (what assimp reads).
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_LT((back.vertices_m[back.triangles[t][k]] - mesh.vertices_m[mesh.triangles[t][k]]).norm(), 1e-7)
          << "triangle " << t << " corner " << k;
  EXPECT_THROW(save_obj(mesh, "/nonexistent-dir/x.obj"), std::runtime_error);
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
