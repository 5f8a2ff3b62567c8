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
