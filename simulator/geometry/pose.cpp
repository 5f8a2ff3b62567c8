#include "simulator/geometry/pose.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace arphys::geometry {

Pose make_pose(const Eigen::Vector3d& position_m, const Eigen::Vector4d& quaternion_wxyz, const std::string& what,
               double norm_tolerance) {
  if (!position_m.allFinite()) {
    std::ostringstream s;
    s << what << ": position_m (" << position_m.transpose() << ") has a non-finite entry";
    throw std::invalid_argument(s.str());
  }
  if (!quaternion_wxyz.allFinite()) {
    std::ostringstream s;
    s << what << ": quaternion (" << quaternion_wxyz.transpose() << ") has a non-finite entry";
    throw std::invalid_argument(s.str());
  }
  const double norm = quaternion_wxyz.norm();
  if (std::abs(norm - 1.0) > norm_tolerance) {
    std::ostringstream s;
    s << what << ": quaternion (w x y z) = (" << quaternion_wxyz.transpose() << ") has norm " << norm
      << ", expected a unit quaternion (|norm - 1| <= " << norm_tolerance << ")";
    throw std::invalid_argument(s.str());
  }
  const Eigen::Quaterniond q(quaternion_wxyz[0] / norm, quaternion_wxyz[1] / norm, quaternion_wxyz[2] / norm,
                             quaternion_wxyz[3] / norm);
  Pose X = Pose::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = position_m;
  return X;
}

Pose rotation_pose(const Eigen::Vector3d& axis, double angle_rad) {
  Pose X = Pose::Identity();
  X.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  return X;
}

Pose translation_pose(const Eigen::Vector3d& p_m) {
  Pose X = Pose::Identity();
  X.translation() = p_m;
  return X;
}

Pose look_at(const Eigen::Vector3d& eye_W, const Eigen::Vector3d& target_W, const Eigen::Vector3d& up_W) {
  const Eigen::Vector3d z = (target_W - eye_W).normalized();
  Eigen::Vector3d x = z.cross(up_W);  // image right: forward x up (up is -y)
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  Pose X = Pose::Identity();
  X.linear() << x, z.cross(x), z;
  X.translation() = eye_W;
  return X;
}

double translation_distance_m(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }

double rotation_distance_rad(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace arphys::geometry
