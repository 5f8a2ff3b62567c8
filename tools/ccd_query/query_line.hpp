#pragma once
#include <string>

#include "simulator/geometry/pose.hpp"

namespace arphys::tools {

// One ccd-query input line: 28 numbers, the poses of A at t=0 and t=1 and of B at t=0
// and t=1, each "x y z qw qx qy qz". Returns an empty string and fills `poses`, or the
// problem (not a number, wrong count, a position beyond kMaxPositionM, a quaternion that is
// not unit). Never throws.
constexpr double kMaxPositionM = 1e6;
std::string parse_query_line(const std::string& line, geometry::Pose poses[4]);

}  // namespace arphys::tools
