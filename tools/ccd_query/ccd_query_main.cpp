// ccd-query MESH_A MESH_B: continuous collision queries from standard input. A file named
// *.pieces.obj is a set of convex pieces (tools/models/convex-decompose) and is swept as
// the simulator sweeps one (conservative advancement, then the hulls' mesh query).
// Each line holds 28 numbers, the poses of A at t=0 and t=1 and of B at t=0 and t=1,
// each "x y z qw qx qy qz" (metres, unit quaternion, world-from-body). Each body
// moves on the screw motion between its two poses. For each line it prints
// "hit toi" and, on a hit, the contact point and the unit normal (from A to B), all
// in the world frame. At the end it prints the number of queries and the median time
// per query on standard error. Bad lines get an error naming the line number.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/convex_piece.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/geometry/pose.hpp"
#include "tools/ccd_query/query_line.hpp"

namespace {

using namespace arphys;

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A mesh, or a convex-piece set when the file is named *.pieces.obj (throws naming the file).
collision::Shape load_shape(const std::string& path) {
  if (ends_with(path, ".pieces.obj")) return collision::Shape::convex_set(collision::load_convex_set(path));
  return collision::Shape::mesh(collision::CollisionMesh::load(path));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Continuous collision queries between two meshes or convex-piece sets (arphys CCD: screw motion, interval\n"
      "arithmetic, OBB trees; conservative advancement for pieces).\n"
      "Reads lines of 28 numbers from standard input: poses of A at t=0, A at t=1, B at t=0, B at t=1, each\n"
      "'x y z qw qx qy qz' (metres, unit quaternion, world-from-body). Prints 'hit toi [px py pz nx ny nz]' per line."};
  std::string mesh_a_path, mesh_b_path;
  double time_tolerance = 1e-9;
  app.add_option("MESH_A", mesh_a_path,
                 "mesh of body A (OBJ/PLY/STL; used as it is), or its convex pieces (a file named *.pieces.obj)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("MESH_B", mesh_b_path, "mesh or convex pieces of body B")->required()->check(CLI::ExistingFile);
  app.add_option("--time-tolerance", time_tolerance, "TOI tolerance in units of t (the TOI is never late)")
      ->check(CLI::Range(1e-15, 1e-2));
  CLI11_PARSE(app, argc, argv);

  collision::Shape shape_a, shape_b;
  try {
    shape_a = load_shape(mesh_a_path);
    shape_b = mesh_b_path == mesh_a_path ? shape_a : load_shape(mesh_b_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ccd-query: %s\n", e.what());
    return 1;
  }
  collision::ContinuousOptions options;
  options.time_tolerance = time_tolerance;

  std::vector<double> micros;
  std::string line;
  long line_number = 0, bad_lines = 0;
  while (std::getline(std::cin, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    geometry::Pose poses[4];
    const std::string problem = tools::parse_query_line(line, poses);
    if (!problem.empty()) {
      std::fprintf(stderr, "ccd-query: line %ld: %s\n", line_number, problem.c_str());
      std::printf("error\n");
      ++bad_lines;
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    const auto result = collision::time_of_impact(shape_a, geometry::ScrewMotion(poses[0], poses[1]), shape_b,
                                                  geometry::ScrewMotion(poses[2], poses[3]), options);
    micros.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    if (result.collides) {
      std::printf("1 %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", result.time_of_impact, result.point_W.x(),
                  result.point_W.y(), result.point_W.z(), result.normal_W.x(), result.normal_W.y(), result.normal_W.z());
    } else {
      std::printf("0 1\n");
    }
  }
  std::fflush(stdout);
  double median = 0;
  if (!micros.empty()) {
    std::nth_element(micros.begin(), micros.begin() + micros.size() / 2, micros.end());
    median = micros[micros.size() / 2];
  }
  std::fprintf(stderr, "ccd-query: %zu queries, median %.1f us per query, %ld bad lines\n", micros.size(), median,
               bad_lines);
  return bad_lines == 0 ? 0 : 3;
}
