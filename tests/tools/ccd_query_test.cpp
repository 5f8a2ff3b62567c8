// The ccd-query command-line contract, run as a real process.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/read_file.hpp"

namespace {

using arphys::testing::read_file;

// Two unit cubes side by side as convex pieces (x from -0.5 to 1.5): a cube sliding in
// from x = 4 meets the second piece halfway (t = 1/2), where the first alone would be met
// at t = 2/3. A piece that is not convex is refused naming the file.
TEST(CcdQueryCli, SweepsAConvexPieceFileAsItsPieces) {
  const auto dir = std::filesystem::temp_directory_path() / ("ccd_query_pieces_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto cube_at = [](double x0, int first) {
    std::ostringstream text;
    for (int k = 0; k < 8; ++k)
      text << "v " << x0 + (k == 1 || k == 2 || k == 5 || k == 6 ? 0.5 : -0.5) << " " << (k % 4 >= 2 ? 0.5 : -0.5) << " "
           << (k >= 4 ? 0.5 : -0.5) << "\n";
    const int faces[12][3] = {{1, 3, 2}, {1, 4, 3}, {5, 6, 7}, {5, 7, 8}, {1, 2, 6}, {1, 6, 5},
                              {2, 3, 7}, {2, 7, 6}, {3, 4, 8}, {3, 8, 7}, {4, 1, 5}, {4, 5, 8}};
    for (const auto& f : faces) text << "f " << f[0] + first << " " << f[1] + first << " " << f[2] + first << "\n";
    return text.str();
  };
  std::ofstream(dir / "two.pieces.obj") << "o part_0\n" << cube_at(0, 0) << "o part_1\n" << cube_at(1, 8);
  std::ofstream(dir / "cube.obj") << cube_at(0, 0);
  // A "piece" that is a tetrahedron with one vertex pushed inside: not convex.
  std::ofstream(dir / "dented.pieces.obj") << "o part_0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.1 0.1 0.1\n"
                                              "f 1 3 2\nf 1 2 4\nf 2 3 5\nf 3 1 4\nf 2 5 4\nf 3 4 5\n";
  std::ofstream(dir / "queries.txt") << "0 0 0 1 0 0 0  0 0 0 1 0 0 0  4 0 0 1 0 0 0  0 0 0 1 0 0 0\n";
  const auto run = [&](const std::string& a) {
    const std::string command = std::string(ARPHYS_BINARY_DIR) + "/tools/ccd_query/ccd-query " + (dir / a).string() + " " +
                                (dir / "cube.obj").string() + " < " + (dir / "queries.txt").string() + " > " +
                                (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
    return WEXITSTATUS(std::system(command.c_str()));
  };
  ASSERT_EQ(run("two.pieces.obj"), 0) << read_file(dir / "err.txt");
  std::istringstream out(read_file(dir / "out.txt"));
  int hit = 0;
  double toi = 0, px = 0;
  out >> hit >> toi >> px;
  EXPECT_EQ(hit, 1);
  EXPECT_NEAR(toi, 0.5, 1e-8);
  EXPECT_LE(toi, 0.5 + 1e-15);
  EXPECT_NEAR(px, 1.5, 1e-7);
  EXPECT_EQ(run("dented.pieces.obj"), 1);
  const std::string err = read_file(dir / "err.txt");
  EXPECT_NE(err.find("dented.pieces.obj"), std::string::npos) << err;
  EXPECT_NE(err.find("convex"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

TEST(CcdQueryCli, AnswersEachLineAndNamesBadLines) {
  const auto dir = std::filesystem::temp_directory_path() / ("ccd_query_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    // A 1 m cube centred on its origin.
    std::ofstream obj(dir / "cube.obj");
    obj << "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
           "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
           "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    std::ofstream in(dir / "queries.txt");
    in << "0 0 0 1 0 0 0  0 0 0 1 0 0 0  3 0 0 1 0 0 0  0 0 0 1 0 0 0\n"   // B slides onto A: TOI 2/3
       << "0 0 0 1 0 0 0  0 0 0 1 0 0 0  3 0 0 1 0 0 0\n"                    // too few numbers
       << "0 0 0 1 0 0 0  0 0 0 1 0 0 0  3 2 0 1 0 0 0  0 2 0 1 0 0 0\n"   // passes beside: no hit
       << "0 0 0 1 0 0 0  0 0 0 1 0 0 0  3 0 0 2 0 0 0  0 0 0 1 0 0 0\n"   // quaternion of norm 2
       << "0 0 0 1 0 0 0  0 0 0 1 0 0 0  3 0 0 1 0 0 0  0 0 0 x 0 0 0\n";  // not a number
  }
  const std::string command = std::string(ARPHYS_BINARY_DIR) + "/tools/ccd_query/ccd-query " + (dir / "cube.obj").string() +
                              " " + (dir / "cube.obj").string() + " < " + (dir / "queries.txt").string() + " > " +
                              (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
  const int status = std::system(command.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 3);  // bad lines make the exit status non-zero
  std::istringstream out(read_file(dir / "out.txt"));
  std::string line;
  std::getline(out, line);
  std::istringstream first(line);
  int hit = 0;
  double toi = 0, px, py, pz, nx, ny, nz;
  first >> hit >> toi >> px >> py >> pz >> nx >> ny >> nz;
  EXPECT_EQ(hit, 1);
  EXPECT_NEAR(toi, 2.0 / 3.0, 1e-8);
  EXPECT_LE(toi, 2.0 / 3.0 + 1e-15);
  EXPECT_NEAR(px, 0.5, 1e-7);
  EXPECT_NEAR(nx, 1.0, 1e-6);
  std::getline(out, line);
  EXPECT_EQ(line, "error");
  std::getline(out, line);
  EXPECT_EQ(line, "0 1");
  const std::string err = read_file(dir / "err.txt");
  EXPECT_NE(err.find("line 2: expected 28 numbers, got 21"), std::string::npos) << err;
  EXPECT_NE(err.find("line 4:"), std::string::npos) << err;
  EXPECT_NE(err.find("quaternion"), std::string::npos) << err;
  EXPECT_NE(err.find("line 5: 'x' is not a number"), std::string::npos) << err;
  EXPECT_NE(err.find("2 queries, median"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
