// The loaders under fuzzing read files, so each input is written to one file per fuzzing
// process; the file is removed when the process exits (runs would otherwise pile them up).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace arphys::fuzz {

// Writes `size` bytes to the process's file for `stem` and `extension` and returns its path
// (empty if it cannot be written). Call with the same stem each time.
inline std::string write_input_file(const char* stem, const char* extension, const uint8_t* data, size_t size) {
  static std::string path;
  if (path.empty()) {
    path = std::string("/tmp/arphys_fuzz_") + stem + "_" + std::to_string(getpid()) + extension;
    std::atexit([] { std::remove(path.c_str()); });
  }
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return "";
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

}  // namespace arphys::fuzz
