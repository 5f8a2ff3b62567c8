#pragma once
#include <string>

#include "simulator/geometry/pose.hpp"

namespace arphys::rendering {

// Parses "x y z qw qx qy qz" (metres, unit quaternion). Throws std::invalid_argument
// naming `what` and the text when it is not seven finite numbers or the quaternion is
// not unit.
geometry::Pose parse_pose(const std::string& text, const std::string& what);

// Where the synthetic camera and the offline renderer look from by default: 0.9 m in
// front of the table's centre and 0.7 m above it, at the centre.
geometry::Pose default_camera_pose();

}  // namespace arphys::rendering
