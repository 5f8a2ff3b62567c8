#pragma once
// Poses to and from Bullet's transforms (the benchmark's Bullet adapters share them).
#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>

namespace arphys::dyn_bench {

inline btTransform to_bt(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.linear());
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()),
                     btVector3(X.translation().x(), X.translation().y(), X.translation().z()));
}

inline Eigen::Isometry3d from_bt(const btTransform& T) {
  const btQuaternion q = T.getRotation();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(T.getOrigin().x(), T.getOrigin().y(), T.getOrigin().z());
  return X;
}

}  // namespace arphys::dyn_bench
