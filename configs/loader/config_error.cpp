#include "configs/loader/config_error.hpp"

namespace arphys::config {
namespace {

std::string format(const std::string& file, int line, const std::string& key, const std::string& problem) {
  std::string where = file;
  if (line > 0) where += ":" + std::to_string(line);
  if (!key.empty()) where += ": " + key;
  return where + ": " + problem;
}

}  // namespace

ConfigError::ConfigError(std::string file, int line, std::string key, std::string problem)
    : std::runtime_error(format(file, line, key, problem)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)),
      problem_(std::move(problem)) {}

}  // namespace arphys::config
