#pragma once
#include <stdexcept>
#include <string>

namespace arphys::config {

// A bad scene or camera file. The message names the file (and line where known),
// the key path (e.g. "objects[2].collision.size_m[1]"), the bad value and what was
// expected, so a user can fix the file without reading code.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, int line, std::string key, std::string problem);
  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 1-based, 0 when unknown
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
  std::string problem_;
};

}  // namespace arphys::config
