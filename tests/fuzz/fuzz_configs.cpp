// Scene and camera files from arbitrary bytes: the loaders must refuse a bad file with
// a ConfigError (naming the file, key and expectation), never crash or throw anything
// else. The first byte picks the loader.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "configs/loader/camera_config.hpp"
#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  // One file per fuzzing process, removed when it exits (runs would otherwise pile them up).
  static const std::string path = [] {
    static std::string name = "/tmp/arphys_fuzz_config_" + std::to_string(getpid()) + ".yaml";
    std::atexit([] { std::remove(name.c_str()); });
    return name;
  }();
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
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
