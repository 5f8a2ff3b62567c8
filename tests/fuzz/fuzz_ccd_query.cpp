// ccd-query's input lines from arbitrary bytes: the parser never throws, and every line
// it accepts is answered by the CCD (two boxes) without crashing, hanging or a NaN.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "simulator/collision/shape_query.hpp"
#include "tools/ccd_query/query_line.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string line(reinterpret_cast<const char*>(data), size);
  arphys::geometry::Pose poses[4];
  if (!arphys::tools::parse_query_line(line, poses).empty()) return 0;
  static const arphys::collision::Shape box = arphys::collision::Shape::box(Eigen::Vector3d(0.2, 0.1, 0.05));
  const auto r = arphys::collision::time_of_impact(box, arphys::geometry::ScrewMotion(poses[0], poses[1]), box,
                                                   arphys::geometry::ScrewMotion(poses[2], poses[3]));
  if (r.collides && !(r.time_of_impact >= 0 && r.time_of_impact <= 1)) std::abort();
  return 0;
}
