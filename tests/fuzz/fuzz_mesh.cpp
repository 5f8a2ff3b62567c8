// Mesh files (OBJ, the format the scenes ship) from arbitrary bytes: load_mesh must
// refuse a bad file with std::runtime_error naming it, and whatever it accepts must be
// usable by the collision code (an OBB tree is built from it).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/arphys_fuzz_mesh_" + std::to_string(getpid()) + ".obj";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  arphys::geometry::TriangleMesh mesh;
  try {
    mesh = arphys::geometry::load_mesh(path);
  } catch (const std::runtime_error&) {
    return 0;
  }
  try {
    arphys::collision::CollisionMesh collision(mesh);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
