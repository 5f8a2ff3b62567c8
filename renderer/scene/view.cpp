#include "renderer/scene/view.hpp"

#include <sstream>
#include <stdexcept>

namespace arphys::rendering {

geometry::Pose parse_pose(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  double v[7];
  for (double& x : v) {
    if (!(in >> x)) {
      throw std::invalid_argument(what + " '" + text + "': expected seven numbers \"x y z qw qx qy qz\" (metres, unit quaternion)");
    }
  }
  std::string rest;
  if (in >> rest) throw std::invalid_argument(what + " '" + text + "': more than seven numbers");
  return geometry::make_pose({v[0], v[1], v[2]}, {v[3], v[4], v[5], v[6]}, what, 1e-3);
}

geometry::Pose default_camera_pose() { return geometry::look_at({0, -0.9, 0.7}, {0, 0, 0}); }

}  // namespace arphys::rendering
