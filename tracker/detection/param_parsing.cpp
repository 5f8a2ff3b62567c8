#include "tracker/detection/param_parsing.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace arphys::tracking {

double parse_param_double(const std::string& name, const std::string& text, double min_value, double max_value) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value) || value < min_value || value > max_value) {
    throw std::invalid_argument("parameter " + name + " = '" + text + "': expected a number in [" +
                                std::to_string(min_value) + ", " + std::to_string(max_value) + "]");
  }
  return value;
}

int parse_param_int(const std::string& name, const std::string& text, int min_value, int max_value) {
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < min_value || value > max_value) {
    throw std::invalid_argument("parameter " + name + " = '" + text + "': expected an integer in [" +
                                std::to_string(min_value) + ", " + std::to_string(max_value) + "]");
  }
  return static_cast<int>(value);
}

bool parse_param_bool(const std::string& name, const std::string& text) {
  if (text == "1" || text == "true" || text == "on") return true;
  if (text == "0" || text == "false" || text == "off") return false;
  throw std::invalid_argument("parameter " + name + " = '" + text + "': expected 0/1, true/false or on/off");
}

}  // namespace arphys::tracking
