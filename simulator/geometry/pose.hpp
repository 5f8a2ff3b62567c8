#pragma once
#include <string>

#include <Eigen/Geometry>

namespace arphys::geometry {

// Poses are Eigen isometries; X_AB is the pose of frame B in frame A (Drake naming),
// so X_AC = X_AB * X_BC and p_A = X_AB * p_B.
using Pose = Eigen::Isometry3d;

// Builds a pose from a position (metres) and a quaternion given as (w, x, y, z).
// Throws std::invalid_argument naming `what` when an entry is not finite or the
// quaternion's norm is further than `norm_tolerance` from 1; the quaternion is
// then renormalised.
Pose make_pose(const Eigen::Vector3d& position_m, const Eigen::Vector4d& quaternion_wxyz,
               const std::string& what = "pose", double norm_tolerance = 1e-6);

// Rotation by angle_rad about a unit axis (no translation).
Pose rotation_pose(const Eigen::Vector3d& axis, double angle_rad);
Pose translation_pose(const Eigen::Vector3d& p_m);

// The pose X_WC of a camera in OpenCV's axes (x right, y down, z forward) at eye_W looking
// at target_W, its image "up" as close to up_W as the view allows (any sideways axis when
// the view is along up_W).
Pose look_at(const Eigen::Vector3d& eye_W, const Eigen::Vector3d& target_W,
             const Eigen::Vector3d& up_W = Eigen::Vector3d::UnitZ());

// Distance measures between two poses: translation in metres, rotation angle in radians.
double translation_distance_m(const Pose& a, const Pose& b);
double rotation_distance_rad(const Pose& a, const Pose& b);

}  // namespace arphys::geometry
