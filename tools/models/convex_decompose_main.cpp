// convex-decompose: turns a mesh into the convex pieces a dynamic body collides as
// (convex_decomposition.hpp), writes them as one OBJ with an object per piece and a
// header saying where they came from, and prints how far they stray from the mesh.
//
//   convex-decompose MESH OUT.pieces.obj [--pieces 8] [--concavity 0.01] [--max-vertices 32]
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "simulator/collision/convex_piece.hpp"
#include "tools/models/approximation_error.hpp"
#include "tools/models/convex_decomposition.hpp"

int main(int argc, char** argv) {
  CLI::App app{"convex-decompose: a mesh as convex pieces (HACD clusters, qhull hulls) for convex_set collision shapes"};
  std::string in, out;
  arphys::tools::DecompositionOptions options;
  int samples = 20000;
  app.add_option("input", in, "closed mesh to decompose (any format assimp reads; holes are capped)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("output", out, "convex-piece OBJ to write (one object per piece)")->required();
  app.add_option("--pieces", options.min_pieces, "fewest pieces: HACD stops merging clusters there")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  app.add_option("--concavity", options.max_concavity, "largest concavity a piece may cover, relative to the mesh's diagonal")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--max-vertices", options.max_vertices_per_piece, "most vertices per piece's hull")
      ->capture_default_str()
      ->check(CLI::Range(4, 1024));
  app.add_option("--samples", samples, "surface points per side for the Hausdorff distances")
      ->capture_default_str()
      ->check(CLI::Range(100, 10000000));
  CLI11_PARSE(app, argc, argv);
  try {
    arphys::geometry::TriangleMesh mesh = arphys::geometry::load_mesh(in);
    const std::size_t capped = arphys::geometry::cap_boundary_loops(mesh);
    const std::vector<arphys::geometry::TriangleMesh> hulls = arphys::tools::decompose_convex(mesh, options);
    std::vector<arphys::collision::ConvexPiece> pieces;
    std::size_t vertices = 0;
    for (std::size_t k = 0; k < hulls.size(); ++k) {
      pieces.emplace_back(hulls[k]);  // refuses what a scene would refuse
      vertices += hulls[k].num_vertices();
    }
    const arphys::tools::ApproximationError e = arphys::tools::approximation_error(mesh, pieces, samples);
    char figures[512];
    std::snprintf(figures, sizeof figures,
                  "%zu pieces, %zu vertices; Hausdorff mesh->pieces %.2f mm, pieces->mesh %.2f mm (%d samples a "
                  "side); volume: union/mesh %.3f, sum/mesh %.3f, intersection/mesh %.3f",
                  pieces.size(), vertices, 1e3 * e.mesh_to_pieces_m, 1e3 * e.pieces_to_mesh_m, e.samples,
                  e.union_volume_m3 / e.mesh_volume_m3, e.pieces_volume_sum_m3 / e.mesh_volume_m3,
                  e.intersection_volume_m3 / e.mesh_volume_m3);
    std::string command = "convex-decompose";
    for (int i = 1; i < argc; ++i)
      command += " " + (i <= 2 ? std::filesystem::path(argv[i]).filename().string() : std::string(argv[i]));
    const std::vector<std::string> header{
        "arphys convex pieces (a convex_set shape's file: one object per piece, body frame of the source)",
        "source: " + std::filesystem::path(in).filename().string() + (capped ? " (holes capped)" : ""),
        "made by: " + command + " (HACD of Bullet 3.24 extras for the clusters, qhull 2020.2 for the hulls)",
        "error (file units read as metres): " + std::string(figures)};
    arphys::geometry::save_obj_parts(hulls, header, out);
    std::printf("%s: %s\n", out.c_str(), figures);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "convex-decompose: %s\n", e.what());
    return 2;
  }
  return 0;
}
