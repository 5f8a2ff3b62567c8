// decimate-quadric: simplifies a triangle mesh by quadric-error edge collapse
// (meshoptimizer's meshopt_simplify, Garland & Heckbert's error metric), which keeps
// the surface's topology: a closed (or manifold-with-holes) mesh stays one, unlike
// vertex clustering (tools/models/decimate_vertex_clustering.py), whose coarse bunnies
// come out with non-manifold edges and cannot be given mass properties. Vertices are a
// subset of the input's (no new positions), so the result never bulges outside it.
//
//   decimate-quadric IN OUT.obj --triangles 1200
#include <CLI/CLI.hpp>
#include <meshoptimizer.h>

#include <cstdio>
#include <vector>

#include "simulator/geometry/triangle_mesh.hpp"

int main(int argc, char** argv) {
  CLI::App app{"decimate-quadric: quadric edge-collapse simplification of a triangle mesh (OBJ, PLY, ... in; OBJ out)"};
  std::string in, out;
  std::size_t triangles = 1200;
  float max_error = 0.02f;
  app.add_option("input", in, "mesh to simplify (any format assimp reads)")->required()->check(CLI::ExistingFile);
  app.add_option("output", out, "Wavefront OBJ to write (v and f lines)")->required();
  app.add_option("--triangles", triangles, "target triangle count")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-error", max_error,
                 "largest deviation allowed, relative to the mesh's extent (the target count is not reached beyond it)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0f));
  CLI11_PARSE(app, argc, argv);
  try {
    const arphys::geometry::TriangleMesh mesh = arphys::geometry::load_mesh(in);
    std::vector<float> positions;
    for (const auto& v : mesh.vertices_m)
      for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(v[k]));
    std::vector<unsigned int> indices;
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) indices.push_back(static_cast<unsigned int>(t[k]));
    std::vector<unsigned int> simplified(indices.size());
    float error = 0;
    simplified.resize(meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(),
                                       mesh.vertices_m.size(), 3 * sizeof(float), 3 * triangles, max_error, 0, &error));
    // meshoptimizer's error is relative to its own scale of the mesh (its largest extent).
    const float scale_m = meshopt_simplifyScale(positions.data(), mesh.vertices_m.size(), 3 * sizeof(float));
    // Keep the vertices still used, in their order, at their input (double) positions.
    std::vector<int> remap(mesh.vertices_m.size(), -1);
    arphys::geometry::TriangleMesh result;
    for (std::size_t i = 0; i < simplified.size(); i += 3) {
      Eigen::Vector3i t;
      for (int k = 0; k < 3; ++k) {
        int& r = remap[simplified[i + k]];
        if (r < 0) {
          r = static_cast<int>(result.vertices_m.size());
          result.vertices_m.push_back(mesh.vertices_m[simplified[i + k]]);
        }
        t[k] = r;
      }
      result.triangles.push_back(t);
    }
    arphys::geometry::save_obj(result, out);
    const auto edges = arphys::geometry::mesh_topology(mesh);
    const auto result_edges = arphys::geometry::mesh_topology(result);
    std::printf("%s: %zu -> %zu triangles, deviation %.3g of the extent (%.3g m); boundary edges %zu -> %zu, "
                "non-manifold edges %zu -> %zu\n",
                out.c_str(), mesh.num_triangles(), result.num_triangles(), error,
                error * scale_m, edges.boundary_edges, result_edges.boundary_edges,
                edges.non_manifold_edges, result_edges.non_manifold_edges);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "decimate-quadric: %s\n", e.what());
    return 2;
  }
  return 0;
}
