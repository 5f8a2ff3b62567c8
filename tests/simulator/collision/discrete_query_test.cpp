#include "simulator/collision/discrete_query.hpp"

#include <gtest/gtest.h>

#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

TEST(DiscreteQuery, SeparationBetweenCubesIsTheGapAndIntersectionIsDetected) {
  const CollisionMesh cube(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  const auto far = separation(cube, geometry::Pose::Identity(), cube, geometry::translation_pose({0.5, 0.05, 0}));
  EXPECT_NEAR(far.distance_m, 0.3, 1e-12);
  EXPECT_NEAR((far.point_B_W - far.point_A_W).norm(), 0.3, 1e-12);
  EXPECT_FALSE(intersects(cube, geometry::Pose::Identity(), cube, geometry::translation_pose({0.5, 0.05, 0})));
  EXPECT_TRUE(intersects(cube, geometry::Pose::Identity(), cube, geometry::translation_pose({0.15, 0.05, 0.02})));
  // Rotated 45 deg about z: the corner comes 0.1 * sqrt(2) closer.
  geometry::Pose turned = geometry::rotation_pose(Eigen::Vector3d::UnitZ(), M_PI / 4);
  turned.translation() = Eigen::Vector3d(0.5, 0, 0);
  EXPECT_NEAR(separation(cube, geometry::Pose::Identity(), cube, turned).distance_m, 0.4 - 0.1 * std::sqrt(2.0), 1e-12);
  // Beyond max_distance_m nothing is examined.
  EXPECT_TRUE(std::isinf(
      separation(cube, geometry::Pose::Identity(), cube, geometry::translation_pose({0.5, 0, 0}), 0.1).distance_m));
}

TEST(DiscreteQuery, ManifoldOfACubeRestingOnACubeCoversTheContactFace) {
  const CollisionMesh base(geometry::make_box_mesh({1, 1, 0.2})), cube(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  // Resting 0.5 mm above the base's top face (z = 0.1), tolerance 1 mm.
  const auto points = contact_manifold(base, geometry::Pose::Identity(), cube, geometry::translation_pose({0, 0, 0.2005}), 1e-3);
  ASSERT_GE(points.size(), 4u);
  Eigen::AlignedBox3d spread;
  for (const auto& p : points) {
    EXPECT_NEAR(p.distance_m, 5e-4, 1e-12);
    EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-9);
    spread.extend(p.point_B_W);
  }
  // The points span the whole 0.2 x 0.2 bottom face, so the support is stable.
  EXPECT_NEAR(spread.sizes().x(), 0.2, 1e-9);
  EXPECT_NEAR(spread.sizes().y(), 0.2, 1e-9);
  EXPECT_TRUE(contact_manifold(base, geometry::Pose::Identity(), cube, geometry::translation_pose({0, 0, 0.21}), 1e-3).empty());
}

// An open surface (a scanned mesh with holes) resting on a solid: its vertices over the
// solid's face are contacts. They were all dropped (an open vertex has no outward
// direction, and the "does the face oppose it" test read 0 >= 0 as "no"), so a bunny
// resting on the holes in its base sank into the table.
TEST(DiscreteQuery, OpenSurfaceVerticesRestingOnASolidAreContacts) {
  const CollisionMesh base(geometry::make_box_mesh({1, 1, 0.2}));
  geometry::TriangleMesh sheet;  // a square of two triangles: open, 0.5 mm above the base's top face
  sheet.vertices_m = {{-0.1, -0.1, 0}, {0.1, -0.1, 0}, {0.1, 0.1, 0}, {-0.1, 0.1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  const CollisionMesh open(sheet);
  ASSERT_FALSE(open.closed());
  for (const bool base_first : {true, false}) {
    const auto points = base_first
                            ? contact_manifold(base, geometry::Pose::Identity(), open, geometry::translation_pose({0, 0, 0.1005}), 1e-3)
                            : contact_manifold(open, geometry::translation_pose({0, 0, 0.1005}), base, geometry::Pose::Identity(), 1e-3);
    ASSERT_EQ(points.size(), 4u) << "base first: " << base_first;  // the four corners
    for (const auto& p : points) {
      EXPECT_NEAR(p.distance_m, 5e-4, 1e-12);
      EXPECT_NEAR(std::abs(p.normal_W.z()), 1.0, 1e-9);
    }
  }
}

TEST(DiscreteQuery, ManifoldOfStackedBoxesGivesCornersAndEdgeCrossings) {
  const CollisionMesh cube(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  // Same size, aligned, 1 um apart: the four coinciding corners, once each per body side.
  const auto aligned = contact_manifold(cube, geometry::Pose::Identity(), cube, geometry::translation_pose({0, 0, 0.200001}), 1e-4);
  ASSERT_GE(aligned.size(), 4u);
  for (const auto& p : aligned) {
    EXPECT_NEAR(p.distance_m, 1e-6, 1e-12);
    EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-12);
  }
  // Turned 45 degrees about z: the faces overlap in an octagon whose corners are edge
  // crossings (no corner of either box lies over the other's face).
  geometry::Pose turned = geometry::rotation_pose(Eigen::Vector3d::UnitZ(), M_PI / 4);
  turned.translation() = Eigen::Vector3d(0, 0, 0.200001);
  const auto crossed = contact_manifold(cube, geometry::Pose::Identity(), cube, turned, 1e-4);
  EXPECT_EQ(crossed.size(), 8u);
  for (const auto& p : crossed) {
    EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-9);
    EXPECT_NEAR(p.distance_m, 1e-6, 1e-12);
    EXPECT_NEAR(std::max(std::abs(p.point_A_W.x()), std::abs(p.point_A_W.y())), 0.1, 1e-9);  // on A's top edges
  }
}

// An edge of a solid (a box) meets an open surface's edge. The contact normal across a
// solid's edge lies between its two faces' normals; edges crossing at another angle touch
// one of the faces and get its normal. Kept as they came, such normals (a box's bottom
// edge pressing a bunny's rim into the box) contradicted the box's face contacts, and the
// solve was infeasible step after step in the 100-bunny scene.
TEST(DiscreteQuery, EdgeContactsOfASolidHaveNormalsBetweenItsFaces) {
  const CollisionMesh box(geometry::make_box_mesh({2, 2, 2}));  // the edge along x at y = z = 1
  const Eigen::Vector3d bisector = Eigen::Vector3d(0, 1, 1).normalized();
  const auto sheet = [](const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) {
    geometry::TriangleMesh mesh;
    mesh.vertices_m = {p0, p1, p2};
    mesh.triangles = {{0, 1, 2}};
    return CollisionMesh(mesh);
  };
  const auto manifold = [&](const CollisionMesh& open, bool box_first) {
    auto points = box_first ? contact_manifold(box, geometry::Pose::Identity(), open, geometry::Pose::Identity(), 1e-3)
                            : contact_manifold(open, geometry::Pose::Identity(), box, geometry::Pose::Identity(), 1e-3);
    if (!box_first)
      for (auto& p : points) p.normal_W = -p.normal_W;  // from the box, as in the other order
    return points;
  };
  // Across the edge, 0.5 mm outside it along the bisector: one contact, normal = the bisector.
  const Eigen::Vector3d out = 5e-4 * bisector;
  const CollisionMesh across = sheet(Eigen::Vector3d(0, 1.3, 0.7) + out, Eigen::Vector3d(0, 0.7, 1.3) + out,
                                     Eigen::Vector3d(0.05, 1.3, 1.3) + out);
  ASSERT_FALSE(across.closed());
  for (const bool box_first : {true, false}) {
    const auto points = manifold(across, box_first);
    ASSERT_EQ(points.size(), 1u) << "box first: " << box_first;
    EXPECT_NEAR(points[0].normal_W.dot(bisector), 1.0, 1e-12);
    EXPECT_NEAR(points[0].distance_m, 5e-4, 1e-12);
  }
  // Along the bisector through the edge into the box: the edges cross with the normal
  // (0, -1, 1) / sqrt(2), square to the bisector. The contact is the top face's.
  const CollisionMesh into = sheet({0, 1.3, 1.3}, {0, 0.7, 0.7}, {0.05, 1.3, 0.7});
  for (const bool box_first : {true, false}) {
    const auto points = manifold(into, box_first);
    ASSERT_EQ(points.size(), 1u) << "box first: " << box_first;
    EXPECT_NEAR(points[0].normal_W.z(), 1.0, 1e-12) << "box first: " << box_first;
  }
  // A sheet resting 0.5 mm above the top face and overhanging the edge, its far end
  // tilted up 0.2 mm: its edges cross the box's a hair outside the edge's normals. They
  // are its support at the rim, with the top face's normal (dropped, a bunny on a table's
  // rim lost its support there and waited at every step).
  const CollisionMesh overhang = sheet({-0.05, 0.8, 1.0005}, {0.05, 0.8, 1.0005}, {0, 1.2, 1.0007});
  for (const bool box_first : {true, false}) {
    int at_rim = 0;
    for (const auto& p : manifold(overhang, box_first)) {
      EXPECT_GE(p.normal_W.dot(bisector), std::sqrt(0.5) - 1e-12) << "box first: " << box_first << ", normal " << p.normal_W.transpose();
      if (std::abs(p.point_A_W.y() - 1) < 1e-9 || std::abs(p.point_B_W.y() - 1) < 1e-9) {
        ++at_rim;
        EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-12);
      }
    }
    EXPECT_EQ(at_rim, 2) << "box first: " << box_first;  // both sloping edges
  }
}

// An open surface's edge passing over a solid's rim, 0.53 mm above its top face and
// 0.79 mm in from the side face: nothing overlaps. Its closest points to the rim lie
// outside the solid, so the edges are apart and the contact is the top face's, at that
// height. (Judged by the sum of the faces' normals, the pair counted as crossed and got
// the side face's normal: a contact 0.79 mm deep where a bunny slid off a table's rim,
// pushed apart at the depenetration speed, and reported as the step's penetration.)
TEST(DiscreteQuery, AnEdgeAboveASolidsRimIsApartWithTheTopFacesNormal) {
  const CollisionMesh box(geometry::make_box_mesh({2, 2, 2}));  // the rim along x at y = z = 1
  const Eigen::Vector3d over_rim(0, 1 - 0.79e-3, 1 + 0.53e-3);   // the sheet edge's closest point
  const Eigen::Vector3d along = Eigen::Vector3d(1, 0.053, 0.079).normalized();  // square to the offset
  geometry::TriangleMesh sheet;
  sheet.vertices_m = {over_rim - 2e-3 * along, over_rim + 2e-3 * along, over_rim + Eigen::Vector3d(0, -3e-3, 3e-3)};
  sheet.triangles = {{0, 1, 2}};
  const CollisionMesh open(sheet);
  for (const bool box_first : {true, false}) {
    auto points = box_first ? contact_manifold(box, geometry::Pose::Identity(), open, geometry::Pose::Identity(), 1e-3)
                            : contact_manifold(open, geometry::Pose::Identity(), box, geometry::Pose::Identity(), 1e-3);
    int at_rim = 0;
    for (auto& p : points) {
      if (!box_first) {
        p.normal_W = -p.normal_W;
        std::swap(p.point_A_W, p.point_B_W);
      }
      EXPECT_GT(p.distance_m, 0.3e-3) << "box first: " << box_first << ", normal " << p.normal_W.transpose();
      if (std::abs(p.point_A_W.y() - 1) < 1e-9 && std::abs(p.point_A_W.z() - 1) < 1e-9) {
        ++at_rim;
        EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-12);
        EXPECT_NEAR(p.distance_m, 0.53e-3, 1e-9);
      }
    }
    EXPECT_EQ(at_rim, 1) << "box first: " << box_first;
  }
}

// Beside a concave edge the solid is behind either face. An L-shaped solid (its inner
// edge along x at y = z = 1, the lower arm's top face z = 1 for y in [1, 2], the upper
// arm's side face y = 1 for z in [1, 2]); a sheet's edge passes 0.3 mm out past the side
// face's plane but 0.8 mm below the top face: inside the lower arm. The edges have
// crossed, and the contact says so (negative, the top face's normal); judged as across a
// convex edge (behind both faces) they would be apart by 0.3 mm.
TEST(DiscreteQuery, AnEdgeInsideASolidBesideItsConcaveEdgeHasCrossed) {
  const double profile[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};  // (y, z), counter-clockwise from +x
  geometry::TriangleMesh l_shape;
  for (const double x : {-1.0, 1.0})
    for (const auto& yz : profile) l_shape.vertices_m.emplace_back(x, yz[0], yz[1]);
  for (int k = 0; k < 6; ++k) {  // sides: back vertex k, front vertex 6 + k
    const int next = (k + 1) % 6;
    l_shape.triangles.emplace_back(k, next, 6 + next);
    l_shape.triangles.emplace_back(k, 6 + next, 6 + k);
  }
  for (const auto& fan : {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(0, 2, 3), Eigen::Vector3i(0, 3, 4), Eigen::Vector3i(0, 4, 5)}) {
    l_shape.triangles.emplace_back(6 + fan[0], 6 + fan[1], 6 + fan[2]);  // front cap, +x
    l_shape.triangles.emplace_back(fan[0], fan[2], fan[1]);              // back cap, -x
  }
  const CollisionMesh solid(l_shape);
  ASSERT_TRUE(solid.closed());
  const Eigen::Vector3d inside(0, 1 + 0.3e-3, 1 - 0.8e-3);  // the sheet edge's closest point
  const Eigen::Vector3d along = Eigen::Vector3d(1, 0.08, 0.03).normalized();  // square to the offset
  geometry::TriangleMesh sheet;
  sheet.vertices_m = {inside - 2e-3 * along, inside + 2e-3 * along, inside + Eigen::Vector3d(0, 3e-3, -3e-3)};
  sheet.triangles = {{0, 1, 2}};
  const CollisionMesh open(sheet);
  int at_edge = 0;
  for (const auto& p : contact_manifold(solid, geometry::Pose::Identity(), open, geometry::Pose::Identity(), 1e-3)) {
    if ((p.point_A_W - Eigen::Vector3d(p.point_A_W.x(), 1, 1)).norm() > 1e-9) continue;
    ++at_edge;
    EXPECT_NEAR(p.normal_W.z(), 1.0, 1e-12);
    EXPECT_NEAR(p.distance_m, -0.8e-3, 1e-9);
  }
  EXPECT_EQ(at_edge, 1);
}

// A bunny rolling slowly on another and on a box table, through contact and crossing:
// with NearbyTrianglePairs the manifold and the intersection test give exactly what a
// full descent gives, at every pose, while most queries reuse the kept pairs.
TEST(DiscreteQuery, NearbyTrianglePairsGiveTheDescentsAnswersBitForBit) {
  const auto bunny = CollisionMesh::load(std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-1k-quadric.obj",
                                         Eigen::Vector3d::Constant(0.8));
  const CollisionMesh table(geometry::make_box_mesh({1.2, 0.8, 0.04}));
  const geometry::Pose X_WA = geometry::translation_pose({0.01, 0.02, 0.03});
  const double tolerance_m = 1e-3;
  for (const CollisionMesh* other : {bunny.get(), &table}) {
    NearbyTrianglePairs nearby;
    int contacts = 0, crossings = 0;
    for (int k = 0; k < 200; ++k) {
      // B sinks through A's surface and turns, 0.1 mm and 1 mrad a query; two jumps.
      geometry::Pose X_WB = geometry::rotation_pose(Eigen::Vector3d(1, 2, 3).normalized(), 1e-3 * k);
      X_WB.translation() = X_WA.translation() + Eigen::Vector3d(0.02, 0.0, other == &table ? 0.045 : 0.075) -
                           Eigen::Vector3d(0, 0, 1e-4 * k) + (k == 80 || k == 81 ? Eigen::Vector3d(0.05, 0, 0) : Eigen::Vector3d::Zero());
      const auto fresh = contact_manifold(*other, X_WA, *bunny, X_WB, tolerance_m);
      const auto kept = contact_manifold(*other, X_WA, *bunny, X_WB, tolerance_m, &nearby);
      ASSERT_EQ(fresh.size(), kept.size()) << "query " << k;
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        EXPECT_EQ(fresh[i].point_A_W, kept[i].point_A_W);
        EXPECT_EQ(fresh[i].normal_W, kept[i].normal_W);
        EXPECT_EQ(fresh[i].distance_m, kept[i].distance_m);
      }
      const auto fresh_crossing = find_intersection(*other, X_WA, *bunny, X_WB);
      const auto kept_crossing = find_intersection(*other, X_WA, *bunny, X_WB, &nearby);
      ASSERT_EQ(fresh_crossing.has_value(), kept_crossing.has_value()) << "query " << k;
      if (fresh_crossing) {
        EXPECT_EQ(fresh_crossing->triangle_A, kept_crossing->triangle_A);
        EXPECT_EQ(fresh_crossing->triangle_B, kept_crossing->triangle_B);
        ++crossings;
      }
      contacts += !fresh.empty();
    }
    // The sequence went from apart through contact into crossing, ...
    EXPECT_GT(contacts, 20);
    EXPECT_GT(crossings, 20);
    // ... and most queries used the kept pairs (a jump or a drift past the spare margin descends).
    EXPECT_GT(nearby.reuses, 3 * nearby.descents);
  }
}

TEST(DiscreteQuery, NearbyTrianglePairsOfOtherMeshesAreNotUsed) {
  const CollisionMesh small(geometry::make_box_mesh({0.2, 0.2, 0.2})), large(geometry::make_box_mesh({0.4, 0.4, 0.4}));
  const geometry::Pose X_WB = geometry::translation_pose({0.1995, 0, 0});
  NearbyTrianglePairs nearby;
  for (int k = 0; k < 3; ++k) contact_manifold(small, geometry::Pose::Identity(), small, X_WB, 1e-3, &nearby);
  ASSERT_GT(nearby.reuses, 0);
  // The same poses with another mesh: the kept node indices belong to the other trees.
  const int descents = nearby.descents;
  EXPECT_EQ(contact_manifold(large, geometry::Pose::Identity(), small, X_WB, 1e-3, &nearby).size(),
            contact_manifold(large, geometry::Pose::Identity(), small, X_WB, 1e-3).size());
  EXPECT_EQ(nearby.descents, descents + 1);
}

TEST(TriangleDistance, CrossingTrianglesAreAtZeroDistance) {
  const Eigen::Vector3d a[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Eigen::Vector3d b[3] = {{0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.3, 0.9, 0.5}};  // pierces a
  EXPECT_EQ(triangle_triangle_distance(a, b), 0.0);
  const Eigen::Vector3d c[3] = {{0.2, 0.2, 0.5}, {0.2, 0.3, 1}, {0.3, 0.9, 0.5}};
  EXPECT_NEAR(triangle_triangle_distance(a, c), 0.5, 1e-15);
}

}  // namespace
}  // namespace arphys::collision
