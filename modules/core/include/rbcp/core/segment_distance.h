#pragma once
/// Distances between points and closed segments in 3D.

#include <Eigen/Core>

namespace rbcp {

/// Distance from point p to the closed segment [a, b] (a point when a == b).
double PointSegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);
/// Distance between the closed segments [a0, a1] and [b0, b1].
double SegmentSegmentDistance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                              const Eigen::Vector3d& b1);

}  // namespace rbcp
