#include "simulator/geometry/triangle_mesh.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

namespace arphys::geometry {

Eigen::AlignedBox3d TriangleMesh::bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& v : vertices_m) box.extend(v);
  return box;
}

namespace {

void append_mesh(const aiMesh* mesh, const aiMatrix4x4& transform, const Eigen::Vector3d& scale, TriangleMesh& out) {
  const int base = static_cast<int>(out.vertices_m.size());
  for (unsigned int i = 0; i < mesh->mNumVertices; ++i) {
    const aiVector3D v = transform * mesh->mVertices[i];
    out.vertices_m.emplace_back(v.x * scale.x(), v.y * scale.y(), v.z * scale.z());
  }
  for (unsigned int f = 0; f < mesh->mNumFaces; ++f) {
    const aiFace& face = mesh->mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines carry no surface
    out.triangles.emplace_back(base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                               base + static_cast<int>(face.mIndices[2]));
  }
}

// Every mesh under the node, depth first, into one mesh (merged) or one part each.
void append_node(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, const Eigen::Vector3d& scale,
                 TriangleMesh* merged, std::vector<TriangleMesh>* parts) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned int m = 0; m < node->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
    if (merged) {
      append_mesh(mesh, transform, scale, *merged);
      continue;
    }
    TriangleMesh part;
    append_mesh(mesh, transform, scale, part);
    if (!part.triangles.empty()) parts->push_back(std::move(part));
  }
  for (unsigned int c = 0; c < node->mNumChildren; ++c)
    append_node(scene, node->mChildren[c], transform, scale, merged, parts);
}

// Writes the mesh's `v` and `f` lines, its vertex numbers starting after `base` earlier ones.
void write_obj_body(std::ostream& out, const TriangleMesh& mesh, std::size_t base) {
  for (const auto& v : mesh.vertices_m) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : mesh.triangles)
    out << "f " << base + t[0] + 1 << " " << base + t[1] + 1 << " " << base + t[2] + 1 << "\n";
}

// The importer's scene of a mesh file; throws naming the path when there is none.
const aiScene* read_scene(Assimp::Importer& importer, const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error("mesh file '" + path + "' does not exist or is not a regular file");
  }
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw std::runtime_error("mesh file '" + path + "' could not be read: " + importer.GetErrorString());
  }
  return scene;
}

}  // namespace

void save_obj(const TriangleMesh& mesh, const std::string& path) { save_obj_parts({mesh}, {}, path); }

void save_obj_parts(const std::vector<TriangleMesh>& parts, const std::vector<std::string>& header,
                    const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out.precision(std::numeric_limits<float>::max_digits10);
  for (const std::string& line : header) out << "# " << line << "\n";
  std::size_t base = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts.size() > 1) out << "o part_" << k << "\n";
    write_obj_body(out, parts[k], base);
    base += parts[k].num_vertices();
  }
  if (!out.flush()) throw std::runtime_error("writing " + path + " failed");
}

TriangleMesh load_mesh(const std::string& path, const Eigen::Vector3d& scale) {
  Assimp::Importer importer;
  const aiScene* scene = read_scene(importer, path);
  TriangleMesh mesh;
  append_node(scene, scene->mRootNode, aiMatrix4x4(), scale, &mesh, nullptr);
  if (mesh.triangles.empty()) throw std::runtime_error("mesh file '" + path + "' holds no triangles");
  return mesh;
}

std::vector<TriangleMesh> load_mesh_parts(const std::string& path, const Eigen::Vector3d& scale) {
  Assimp::Importer importer;
  const aiScene* scene = read_scene(importer, path);
  std::vector<TriangleMesh> parts;
  append_node(scene, scene->mRootNode, aiMatrix4x4(), scale, nullptr, &parts);
  if (parts.empty()) throw std::runtime_error("mesh file '" + path + "' holds no triangles");
  return parts;
}

MeshTopology mesh_topology(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> edge_use;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++edge_use[{std::min(a, b), std::max(a, b)}];
    }
  }
  MeshTopology topology;
  for (const auto& [edge, count] : edge_use) {
    if (count == 1) ++topology.boundary_edges;
    if (count > 2) ++topology.non_manifold_edges;
  }
  return topology;
}

std::size_t cap_boundary_loops(TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> edge_use;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++edge_use[{std::min(a, b), std::max(a, b)}];
    }
  }
  // Directed boundary edges a->b as they run in their one triangle.
  std::multimap<int, int> next;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (edge_use[{std::min(a, b), std::max(a, b)}] == 1) next.emplace(a, b);
    }
  }
  std::size_t loops = 0;
  while (!next.empty()) {
    std::vector<int> loop;
    auto it = next.begin();
    const int start = it->first;
    int current = start;
    while (it != next.end()) {
      loop.push_back(current);
      const int to = it->second;
      next.erase(it);
      current = to;
      if (current == start) break;
      it = next.find(current);
    }
    if (loop.size() < 3) continue;  // a dangling edge pair: nothing to cap
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : loop) centroid += mesh.vertices_m[v];
    centroid /= static_cast<double>(loop.size());
    const int c = static_cast<int>(mesh.vertices_m.size());
    mesh.vertices_m.push_back(centroid);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      mesh.triangles.emplace_back(b, a, c);  // reversed: the cap sees the edge from the other side
    }
    ++loops;
  }
  return loops;
}

TriangleMesh make_box_mesh(const Eigen::Vector3d& size_m) {
  TriangleMesh mesh;
  const Eigen::Vector3d h = 0.5 * size_m;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices_m.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

TriangleMesh make_sphere_mesh(double radius_m, int subdivisions) {
  // Icosahedron, each face split in four `subdivisions` times, vertices pushed to the sphere.
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh mesh;
  mesh.vertices_m = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                     {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : mesh.vertices_m) v.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      mesh.vertices_m.push_back((mesh.vertices_m[a] + mesh.vertices_m[b]).normalized());
      const int index = static_cast<int>(mesh.vertices_m.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> finer;
    for (const auto& t : mesh.triangles) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      finer.emplace_back(t[0], ab, ca);
      finer.emplace_back(t[1], bc, ab);
      finer.emplace_back(t[2], ca, bc);
      finer.emplace_back(ab, bc, ca);
    }
    mesh.triangles = std::move(finer);
  }
  for (auto& v : mesh.vertices_m) v *= radius_m;
  return mesh;
}

}  // namespace arphys::geometry
