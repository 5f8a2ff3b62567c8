// Mesh files (OBJ, the format the scenes ship) from arbitrary bytes: load_mesh must
// refuse a bad file with std::runtime_error naming it, and whatever it accepts must be
// usable by the collision code (an OBB tree is built from it).
#include <cstdint>
#include <stdexcept>
#include <string>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/geometry/triangle_mesh.hpp"
#include "tests/fuzz/fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = arphys::fuzz::write_input_file("mesh", ".obj", data, size);
  if (path.empty()) return 0;
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
