#include "simulator/collision/obb_tree.hpp"

#include <gtest/gtest.h>

#include <functional>

#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::collision {
namespace {

bool box_contains(const Obb& box, const Eigen::Vector3d& p, double slack) {
  const Eigen::Vector3d local = box.axes.transpose() * (p - box.center);
  return (local.cwiseAbs() - box.half_extents_m).maxCoeff() <= slack;
}

TEST(ObbTree, EveryNodeBoxContainsItsTrianglesAndLeavesCoverTheMesh) {
  const auto mesh = geometry::load_mesh(std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-5k.obj");
  const ObbTree tree(mesh);
  EXPECT_EQ(tree.degenerate_triangles_skipped(), 0u);
  std::vector<int> seen(mesh.num_triangles(), 0);
  // Collect the triangles under each node and check its box holds all their corners.
  std::function<std::vector<int>(int)> visit = [&](int index) -> std::vector<int> {
    const ObbNode& node = tree.nodes()[index];
    std::vector<int> triangles;
    if (node.is_leaf()) {
      triangles.push_back(node.triangle);
      ++seen[node.triangle];
    } else {
      for (int child : {node.first_child, node.first_child + 1}) {
        auto sub = visit(child);
        triangles.insert(triangles.end(), sub.begin(), sub.end());
      }
    }
    for (int t : triangles)
      for (int k = 0; k < 3; ++k)
        EXPECT_TRUE(box_contains(node.box, mesh.vertices_m[mesh.triangles[t][k]], 1e-12)) << "node " << index;
    EXPECT_NEAR((node.box.axes.transpose() * node.box.axes - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    return triangles;
  };
  visit(0);
  for (std::size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
  EXPECT_LT(tree.depth(), 40);  // the mean split keeps the tree balanced enough
}

TEST(ObbTree, DegenerateTrianglesAreSkippedAndCounted) {
  geometry::TriangleMesh soup = geometry::make_box_mesh({1, 1, 1});
  const int n = static_cast<int>(soup.vertices_m.size());
  soup.vertices_m.push_back({0, 0, 0});
  soup.vertices_m.push_back({1, 0, 0});
  soup.vertices_m.push_back({2, 0, 0});                          // collinear with the two above
  soup.triangles.push_back({n, n + 1, n + 2});                    // zero area
  soup.triangles.push_back({0, 0, 1});                            // repeated index
  const ObbTree tree(soup);
  EXPECT_EQ(tree.degenerate_triangles_skipped(), 2u);
  EXPECT_EQ(tree.nodes().size(), 2 * 12 - 1u);
}

TEST(ObbTree, AMeshWithOnlyDegenerateTrianglesIsRejected) {
  geometry::TriangleMesh soup;
  soup.vertices_m = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  soup.triangles = {{0, 1, 2}};
  EXPECT_THROW(ObbTree{soup}, std::invalid_argument);
}

}  // namespace
}  // namespace arphys::collision
