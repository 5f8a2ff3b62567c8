#pragma once
// Poses spelled the short way the tests place bodies: a position, and a turn given as a
// rotation matrix or as an axis and an angle; and random poses from a test's own generator.
#include <random>

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

// A vector uniform in [-1, 1]^3 from the test's own generator, drawn x, y, z in order
// (Eigen's Random draws on std::rand, shared by every test in a binary).
inline Eigen::Vector3d random_vector(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const double x = u(rng), y = u(rng), z = u(rng);
  return {x, y, z};
}

// A uniformly random turn and a translation within max_translation_m along each axis.
inline geometry::Pose random_pose(std::mt19937& rng, double max_translation_m) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  geometry::Pose X = geometry::Pose::Identity();
  X.linear() = q.normalized().toRotationMatrix();
  X.translation() = max_translation_m * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return X;
}

}  // namespace arphys::testing
