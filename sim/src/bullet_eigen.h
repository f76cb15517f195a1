#pragma once
/// Conversions between Eigen and Bullet (double precision) types. Private to the simulator.

#include <LinearMath/btQuaternion.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rbcp::sim {

static_assert(sizeof(btScalar) == sizeof(double), "the simulator needs Bullet in double precision");

inline btVector3 ToBt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }

inline btMatrix3x3 ToBt(const Eigen::Matrix3d& R) {
  return btMatrix3x3(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
}

inline btTransform ToBt(const Eigen::Isometry3d& T) { return btTransform(ToBt(Eigen::Matrix3d(T.linear())), ToBt(Eigen::Vector3d(T.translation()))); }

/// The quaternion q with quatRotate(q, v) == R v.
inline btQuaternion ToBtQuaternion(const Eigen::Matrix3d& R) {
  btQuaternion q;
  ToBt(R).getRotation(q);
  return q;
}

inline Eigen::Vector3d ToEigen(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

inline Eigen::Matrix3d ToEigen(const btMatrix3x3& m) {
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) R(i, j) = m[i][j];
  }
  return R;
}

inline Eigen::Isometry3d ToEigen(const btTransform& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = ToEigen(t.getBasis());
  T.translation() = ToEigen(t.getOrigin());
  return T;
}

}  // namespace rbcp::sim
