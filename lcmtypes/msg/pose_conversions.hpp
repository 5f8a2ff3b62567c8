#pragma once
#include <string>

#include <Eigen/Geometry>

#include "arphys/pose_t.hpp"

namespace arphys::msg {

// Tolerance on |q| - 1 for a quaternion received in a message.
constexpr double kQuaternionNormTolerance = 1e-6;

arphys::pose_t to_message(const Eigen::Isometry3d& X);

// Throws std::invalid_argument naming `what` and the bad value when the pose has a
// non-finite entry or a quaternion norm further than kQuaternionNormTolerance from 1.
// The accepted quaternion is renormalised.
Eigen::Isometry3d from_message(const arphys::pose_t& pose, const std::string& what = "pose");

// The same check without throwing: returns an empty string when valid, else the reason.
std::string pose_problem(const arphys::pose_t& pose);

void to_array(const Eigen::Vector3d& v, double out[3]);
Eigen::Vector3d from_array(const double in[3]);

}  // namespace arphys::msg
