#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <vector>

#include "renderer/drawing/gpu_mesh.hpp"

namespace arphys::rendering {

GpuMesh::GpuMesh(const geometry::TriangleMesh& mesh) {
  // Interleaved position + normal; normals summed over incident triangles weighted by
  // area (the cross product's length), which smooths a scanned mesh without rounding edges
  // of a box more than one triangle's width.
  std::vector<Eigen::Vector3f> normals(mesh.num_vertices(), Eigen::Vector3f::Zero());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d n = (mesh.vertices_m[t[1]] - mesh.vertices_m[t[0]]).cross(mesh.vertices_m[t[2]] - mesh.vertices_m[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n.cast<float>();
  }
  std::vector<float> interleaved;
  interleaved.reserve(mesh.num_vertices() * 6);
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    const Eigen::Vector3f p = mesh.vertices_m[i].cast<float>();
    const Eigen::Vector3f n = normals[i].norm() > 0 ? normals[i].normalized() : Eigen::Vector3f::UnitZ();
    interleaved.insert(interleaved.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
  }
  std::vector<unsigned> indices;
  indices.reserve(mesh.num_triangles() * 3);
  for (const auto& t : mesh.triangles) indices.insert(indices.end(), {unsigned(t[0]), unsigned(t[1]), unsigned(t[2])});
  num_indices_ = indices.size();

  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(1, &vertex_buffer_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glBufferData(GL_ARRAY_BUFFER, interleaved.size() * sizeof(float), interleaved.data(), GL_STATIC_DRAW);
  glGenBuffers(1, &index_buffer_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(unsigned), indices.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
}

GpuMesh::~GpuMesh() {
  glDeleteBuffers(1, &index_buffer_);
  glDeleteBuffers(1, &vertex_buffer_);
  glDeleteVertexArrays(1, &vao_);
}

void GpuMesh::draw() const {
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(num_indices_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace arphys::rendering
