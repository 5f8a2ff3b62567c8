// Scene and camera files from arbitrary bytes: the loaders must refuse a bad file with
// a ConfigError (naming the file, key and expectation), never crash or throw anything
// else. The first byte picks the loader.
#include <cstdint>
#include <string>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "tests/fuzz/fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string path = arphys::fuzz::write_input_file("config", ".yaml", data + 1, size - 1);
  if (path.empty()) return 0;
  try {
    if (data[0] % 2) {
      arphys::config::load_camera(path);
    } else {
      arphys::config::load_scene(path);
    }
  } catch (const arphys::config::ConfigError&) {
  }
  return 0;
}
