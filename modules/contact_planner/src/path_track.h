#pragma once
/// Following the root path: the path interpolated between its samples with a smoothed heading,
/// and the level base poses along it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "rbcp/core/root_path_sample.h"

namespace rbcp::contact_planner_detail {

/// `a` wrapped into [-pi, pi) by fmod after adding pi. It rounds differently from WrapAngle
/// (rbcp/core/angle.h) in the last bits; the planner's base headings, and so its plans, are
/// those of this one.
double WrapPi(double a);

/// Rotation by `yaw` about the world z axis.
Eigen::Matrix3d Yaw(double yaw);

/// A root pose on the path: position and heading.
struct PathPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};

/// The root path, linearly interpolated between its samples, with its heading averaged over
/// +- yaw_window [s] (shrunk at the ends so the first and last headings are kept).
class PathTrack {
 public:
  /// `samples`: at least one, times increasing.
  PathTrack(std::vector<RootPathSample> samples, double yaw_window);
  double Begin() const { return s_.front().t; }
  double End() const { return s_.back().t; }
  /// The pose at path time t (clamped to [Begin(), End()]).
  PathPose At(double t) const;

 private:
  std::vector<RootPathSample> s_;
};

/// Level base pose at a path pose.
Eigen::Isometry3d PathBasePose(const PathPose& pose);

/// The path pose `lead` [s] after t, or earlier if the heading turns by more than max_lead_yaw
/// [rad] before (a target far round a turn is no useful foothold).
PathPose LeadPose(const PathTrack& path, double t, double lead, double max_lead_yaw);

}  // namespace rbcp::contact_planner_detail
