#pragma once
#include <cstddef>

#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::rendering {

// A triangle mesh in GL buffers (positions and area-weighted vertex normals), drawn with
// the overlay program. Needs the GL context current when made, drawn and destroyed.
class GpuMesh {
 public:
  explicit GpuMesh(const geometry::TriangleMesh& mesh);
  ~GpuMesh();
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  void draw() const;
  std::size_t num_triangles() const { return num_indices_ / 3; }

 private:
  unsigned vao_ = 0, vertex_buffer_ = 0, index_buffer_ = 0;
  std::size_t num_indices_ = 0;
};

}  // namespace arphys::rendering
