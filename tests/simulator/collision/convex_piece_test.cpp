// Convex pieces: the shipped bunny's pieces load and are polyhedra; what is not one is
// refused with the file, the piece and the reason.
#include "simulator/collision/convex_piece.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_distance.hpp"

namespace arphys::collision {
namespace {

const std::string kBunnyPieces = std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-1k-quadric.pieces.obj";

std::string refusal(geometry::TriangleMesh mesh) {
  try {
    ConvexPiece piece(std::move(mesh));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

TEST(ConvexPiece, BoxHasSixFacesTwelveEdgesAndItsThickness) {
  const ConvexPiece box(geometry::make_box_mesh({0.4, 0.2, 0.1}));
  EXPECT_EQ(box.vertices_m().size(), 8u);
  EXPECT_EQ(box.faces().size(), 6u);
  EXPECT_EQ(box.edges().size(), 12u);
  EXPECT_NEAR(box.volume_m3(), 0.008, 1e-15);
  EXPECT_NEAR(box.half_thickness_m(), 0.05, 1e-15);
  for (const auto& face : box.faces()) {
    EXPECT_EQ(face.polygon.size(), 4u);
    // Counter-clockwise seen from outside: the polygon's own normal is the face's.
    const auto& v = box.vertices_m();
    const Eigen::Vector3d n = (v[face.polygon[1]] - v[face.polygon[0]]).cross(v[face.polygon[2]] - v[face.polygon[1]]);
    EXPECT_GT(n.normalized().dot(face.normal), 0.999999);
    EXPECT_NEAR(face.normal.dot(v[face.polygon[0]]), face.offset_m, 1e-15);
  }
  EXPECT_EQ(box.support({1, 1, 1}), box.support({1, 1, 1}));
  EXPECT_NEAR(box.vertices_m()[box.support({1, 1, 1})].sum(), 0.35, 1e-15);
}

// The boxes' gap never exceeds the pieces' distance (GJK's), and it is the distance for two
// boxes face to face.
TEST(ConvexPiece, BoxGapIsALowerBoundOnTheDistance) {
  const auto set = load_convex_set(kBunnyPieces, Eigen::Vector3d::Constant(0.8));
  std::srand(7);
  int tight = 0, trials = 0;
  for (int k = 0; k < 2000; ++k) {
    const ConvexPiece& a = set->pieces[k % 10];
    const ConvexPiece& b = set->pieces[(k / 10) % 10];
    const geometry::Pose X_WA = geometry::Pose::Identity();
    geometry::Pose X_WB = geometry::Pose::Identity();
    X_WB.linear() = Eigen::Quaterniond(Eigen::Vector4d::Random()).normalized().toRotationMatrix();
    X_WB.translation() = 0.15 * Eigen::Vector3d::Random();
    const double gap = box_gap_lower_bound_m(a.box_m(), b.box_m(), X_WA.inverse() * X_WB);
    const ConvexDistance d = convex_distance(a, X_WA, b, X_WB);
    if (d.lower_m <= 0) continue;
    ++trials;
    EXPECT_LE(gap, d.upper_m + 1e-12) << "trial " << k;
    tight += gap > 0.5 * d.lower_m;
  }
  std::printf("box gap: %d of %d apart piece pairs within half their distance\n", tight, trials);
  EXPECT_GT(trials, 1000);
  EXPECT_GT(tight, trials / 10);  // (a bound that is always 0 would pass the first check)
  const ConvexPiece box(geometry::make_box_mesh({0.2, 0.2, 0.2}));
  geometry::Pose X_AB = geometry::Pose::Identity();
  X_AB.translation() = Eigen::Vector3d(0.25, 0.01, 0);
  EXPECT_NEAR(box_gap_lower_bound_m(box.box_m(), box.box_m(), X_AB), 0.05, 1e-15);
}

TEST(ConvexPiece, ShippedBunnyPiecesArePolyhedra) {
  const auto set = load_convex_set(kBunnyPieces, Eigen::Vector3d::Constant(0.8));
  ASSERT_EQ(set->pieces.size(), 10u);
  double volume = 0, thinnest = 1;
  for (const ConvexPiece& piece : set->pieces) {
    EXPECT_GT(piece.half_thickness_m(), 1e-3);
    thinnest = std::min(thinnest, piece.half_thickness_m());
    EXPECT_GE(piece.faces().size(), 4u);
    // Euler's formula for a convex polyhedron's faces, edges and vertices.
    EXPECT_EQ(piece.vertices_m().size() + piece.faces().size(), piece.edges().size() + 2);
    volume += piece.volume_m3();
  }
  // The scaled bunny is about 0.12 m across; its pieces hold about its volume.
  EXPECT_GT(volume, 2e-4);
  EXPECT_LT(volume, 6e-4);
  EXPECT_EQ(set->half_thickness_m, thinnest);
  EXPECT_TRUE(set->hulls->closed());
  EXPECT_EQ(set->hulls->mesh().num_vertices(), 297u);
}

TEST(ConvexPiece, RefusesWhatIsNoPolyhedronWithTheReason) {
  const geometry::TriangleMesh box = geometry::make_box_mesh({0.1, 0.1, 0.1});
  geometry::TriangleMesh open = box;
  open.triangles.pop_back();
  EXPECT_TRUE(starts_with(refusal(open), "not closed")) << refusal(open);
  geometry::TriangleMesh dented = box;
  dented.vertices_m[0] *= 0.5;  // a corner pushed in: the faces around it fold inwards
  EXPECT_TRUE(starts_with(refusal(dented), "not convex")) << refusal(dented);
  geometry::TriangleMesh nan = box;
  nan.vertices_m[3].x() = std::nan("");
  EXPECT_TRUE(starts_with(refusal(nan), "non-finite")) << refusal(nan);
  geometry::TriangleMesh few;
  few.vertices_m = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  few.triangles = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_TRUE(starts_with(refusal(few), "empty")) << refusal(few);
  geometry::TriangleMesh inside_out = box;
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  EXPECT_TRUE(starts_with(refusal(inside_out), "not convex")) << refusal(inside_out);
  geometry::TriangleMesh flat = box;
  for (auto& v : flat.vertices_m) v.z() = 0;
  EXPECT_TRUE(starts_with(refusal(flat), "degenerate")) << refusal(flat);
}

TEST(ConvexPiece, FileWithABadPieceNamesTheFileAndThePiece) {
  const std::string path = ::testing::TempDir() + "/bad.pieces.obj";
  geometry::TriangleMesh good = geometry::make_box_mesh({0.1, 0.1, 0.1}), open = good;
  open.triangles.pop_back();
  geometry::save_obj_parts({good, open}, {"a closed box, then one with a face missing"}, path);
  try {
    load_convex_set(path);
    FAIL() << "an open piece was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("piece 1: not closed"), std::string::npos) << what;
  }
  std::remove(path.c_str());
  EXPECT_THROW(load_convex_set(path), std::invalid_argument);  // missing file: named too
}

}  // namespace
}  // namespace arphys::collision
