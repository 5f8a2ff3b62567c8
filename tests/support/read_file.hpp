#pragma once
// A file's whole text, for tests that read what a process wrote (empty if it is missing).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace arphys::testing {

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace arphys::testing
