#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace arphys::geometry {

// An indexed triangle mesh in its own body frame, metres. May be a polygon soup
// (open, non-manifold); functions that need a closed surface say so.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices_m;
  std::vector<Eigen::Vector3i> triangles;  // vertex indices, counter-clockwise seen from outside

  std::size_t num_vertices() const { return vertices_m.size(); }
  std::size_t num_triangles() const { return triangles.size(); }
  Eigen::AlignedBox3d bounds() const;
};

// Loads OBJ, PLY, STL (anything assimp reads) as one mesh: all sub-meshes merged,
// node transforms applied, faces triangulated, identical vertices joined, then
// every vertex multiplied component-wise by `scale`. Nothing else is changed
// (no recentring). Throws std::runtime_error naming the path when the file is
// missing, cannot be parsed or holds no triangles.
TriangleMesh load_mesh(const std::string& path, const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

// Loads a file's meshes one by one (an OBJ's `o` objects, in file order), each
// triangulated with its identical vertices joined and scaled; errors as load_mesh.
// Convex-piece files (collision/convex_piece.hpp) hold one piece per object.
std::vector<TriangleMesh> load_mesh_parts(const std::string& path,
                                          const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

// Writes the mesh as Wavefront OBJ (`v` and `f` lines only), coordinates to 9
// significant digits: what load_mesh keeps (assimp reads single precision). Throws
// std::runtime_error naming the path when it cannot be written.
void save_obj(const TriangleMesh& mesh, const std::string& path);
// Writes the parts as one OBJ, one `o part_K` object each, after the header lines
// (each written as an OBJ comment), at the same precision as save_obj.
void save_obj_parts(const std::vector<TriangleMesh>& parts, const std::vector<std::string>& header,
                    const std::string& path);

// Boundary edges (used by exactly one triangle) and non-manifold edges (more than two).
struct MeshTopology {
  std::size_t boundary_edges = 0;
  std::size_t non_manifold_edges = 0;
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
};
MeshTopology mesh_topology(const TriangleMesh& mesh);

// Closes each boundary loop with a fan of triangles around the loop's centroid,
// oriented consistently with the neighbouring triangles. Scanned meshes (the
// Stanford bunny has small holes in its base) need this before volume integration.
// Returns the number of loops closed.
std::size_t cap_boundary_loops(TriangleMesh& mesh);

// Simple closed meshes for tests and primitives' render meshes.
TriangleMesh make_box_mesh(const Eigen::Vector3d& size_m);
TriangleMesh make_sphere_mesh(double radius_m, int subdivisions);

}  // namespace arphys::geometry
