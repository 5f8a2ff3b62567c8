// convex-decompose, run as a real process: the bunny's pieces it writes are what a scene
// accepts and what ships, with their error in the header; a box is its own one piece; a
// missing input is named.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_piece.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace {

const std::string kModels = std::string(ARPHYS_SOURCE_DIR) + "/configs/models/";
const std::string kTool = std::string(ARPHYS_BINARY_DIR) + "/tools/models/convex-decompose";

int run(const std::string& arguments) { return WEXITSTATUS(std::system((kTool + " " + arguments).c_str())); }

std::string text_of(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ConvexDecompose, TheBunnysPiecesAreTheShippedOnesWithTheirError) {
  const auto out = std::filesystem::path(::testing::TempDir()) / "bunny.pieces.obj";
  ASSERT_EQ(run(kModels + "stanford-bunny-1k-quadric.obj " + out.string() + " > /dev/null"), 0);
  const auto made = arphys::collision::load_convex_set(out.string());
  const auto shipped = arphys::collision::load_convex_set(kModels + "stanford-bunny-1k-quadric.pieces.obj");
  ASSERT_EQ(made->pieces.size(), shipped->pieces.size());
  EXPECT_EQ(made->hulls->mesh().num_vertices(), shipped->hulls->mesh().num_vertices());
  const std::string header = text_of(out);
  EXPECT_NE(header.find("# source: stanford-bunny-1k-quadric.obj (holes capped)"), std::string::npos);
  EXPECT_NE(header.find("Hausdorff mesh->pieces 5.67 mm, pieces->mesh 6.46 mm"), std::string::npos) << header.substr(0, 600);
  // The union of the pieces holds the bunny's volume to a few percent.
  EXPECT_NE(header.find("union/mesh 0.997"), std::string::npos);
}

TEST(ConvexDecompose, ABoxIsOnePieceThatMatchesIt) {
  const auto dir = std::filesystem::path(::testing::TempDir());
  arphys::geometry::save_obj(arphys::geometry::make_box_mesh({0.3, 0.2, 0.1}), (dir / "box.obj").string());
  const auto out = dir / "box.pieces.obj";
  ASSERT_EQ(run((dir / "box.obj").string() + " " + out.string() + " --pieces 1 > " + (dir / "box.txt").string()), 0);
  const auto set = arphys::collision::load_convex_set(out.string());
  ASSERT_EQ(set->pieces.size(), 1u);
  EXPECT_NEAR(set->pieces[0].volume_m3(), 0.006, 1e-9);
  EXPECT_NE(text_of(dir / "box.txt").find("Hausdorff mesh->pieces 0.00 mm, pieces->mesh 0.00 mm"), std::string::npos)
      << text_of(dir / "box.txt");
}

TEST(ConvexDecompose, AMissingInputIsNamedAndFails) {
  const auto err = std::filesystem::path(::testing::TempDir()) / "decompose_err.txt";
  EXPECT_NE(run("/nonexistent/bunny.obj /dev/null 2> " + err.string()), 0);
  EXPECT_NE(text_of(err).find("/nonexistent/bunny.obj"), std::string::npos) << text_of(err);
}

}  // namespace
