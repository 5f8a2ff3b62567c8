#include "lcmtypes/msg/pose_conversions.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace arphys::msg {

arphys::pose_t to_message(const Eigen::Isometry3d& X) {
  arphys::pose_t out{};
  to_array(X.translation(), out.position_m);
  Eigen::Quaterniond q(X.rotation());
  q.normalize();
  out.orientation_wxyz[0] = q.w();
  out.orientation_wxyz[1] = q.x();
  out.orientation_wxyz[2] = q.y();
  out.orientation_wxyz[3] = q.z();
  return out;
}

std::string pose_problem(const arphys::pose_t& pose) {
  std::ostringstream why;
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(pose.position_m[i])) {
      why << "position_m[" << i << "] is " << pose.position_m[i] << " (expected a finite number)";
      return why.str();
    }
  }
  double norm2 = 0;
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(pose.orientation_wxyz[i])) {
      why << "orientation_wxyz[" << i << "] is " << pose.orientation_wxyz[i] << " (expected a finite number)";
      return why.str();
    }
    norm2 += pose.orientation_wxyz[i] * pose.orientation_wxyz[i];
  }
  const double norm = std::sqrt(norm2);
  if (std::abs(norm - 1.0) > kQuaternionNormTolerance) {
    why << "orientation_wxyz has norm " << norm << " (expected a unit quaternion, |norm - 1| <= "
        << kQuaternionNormTolerance << ")";
    return why.str();
  }
  return {};
}

Eigen::Isometry3d from_message(const arphys::pose_t& pose, const std::string& what) {
  const std::string problem = pose_problem(pose);
  if (!problem.empty()) throw std::invalid_argument(what + ": " + problem);
  Eigen::Quaterniond q(pose.orientation_wxyz[0], pose.orientation_wxyz[1], pose.orientation_wxyz[2],
                       pose.orientation_wxyz[3]);
  q.normalize();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = from_array(pose.position_m);
  return X;
}

void to_array(const Eigen::Vector3d& v, double out[3]) {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

Eigen::Vector3d from_array(const double in[3]) { return {in[0], in[1], in[2]}; }

}  // namespace arphys::msg
