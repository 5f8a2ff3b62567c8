#pragma once
// Poses spelled the short way the scene tests place bodies: a position, and a turn given as
// a rotation matrix or as an axis and an angle.
#include <Eigen/Geometry>

#include "simulator/geometry/pose.hpp"

namespace arphys::testing {

inline geometry::Pose at(const Eigen::Vector3d& p, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  geometry::Pose X = geometry::Pose::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

inline geometry::Pose at(const Eigen::Vector3d& p, const Eigen::Vector3d& axis, double angle_rad) {
  geometry::Pose X = geometry::rotation_pose(axis.normalized(), angle_rad);
  X.translation() = p;
  return X;
}

}  // namespace arphys::testing
