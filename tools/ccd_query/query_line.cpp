#include "tools/ccd_query/query_line.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace arphys::tools {

std::string parse_query_line(const std::string& line, geometry::Pose poses[4]) {
  constexpr int kNumbersPerLine = 28;
  std::istringstream in(line);
  double values[kNumbersPerLine];
  int count = 0;
  std::string token;
  while (in >> token) {
    if (count == kNumbersPerLine) return "more than 28 numbers";
    try {
      std::size_t used = 0;
      values[count] = std::stod(token, &used);
      if (used != token.size()) throw std::invalid_argument(token);
    } catch (const std::exception&) {
      return "'" + token + "' is not a number";
    }
    ++count;
  }
  if (count != kNumbersPerLine) return "expected 28 numbers, got " + std::to_string(count);
  static const char* names[4] = {"A at t=0", "A at t=1", "B at t=0", "B at t=1"};
  for (int k = 0; k < 4; ++k) {
    const double* v = values + 7 * k;
    for (int i = 0; i < 3; ++i) {
      // Beyond a thousand kilometres the interval bounds of a screw motion lose every digit.
      if (!(std::abs(v[i]) <= kMaxPositionM)) {
        return std::string("position of ") + names[k] + " is " + std::to_string(v[i]) + " (expected |x| <= 1e6 m)";
      }
    }
    try {
      poses[k] = geometry::make_pose({v[0], v[1], v[2]}, {v[3], v[4], v[5], v[6]}, names[k]);
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  return "";
}

}  // namespace arphys::tools
