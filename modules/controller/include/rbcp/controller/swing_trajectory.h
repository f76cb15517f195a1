#pragma once
/// The path of a swinging foot: a cubic Bezier curve from the lift-off point to a point just below
/// the new foothold, leaving and arriving along the surface normals, raised until it clears the
/// terrain under it, run on a smooth (zero end velocity) time scaling.

#include <Eigen/Core>
#include <array>

#include "rbcp/controller/controller_config.h"
#include "rbcp/core/triangle_mesh.h"

namespace rbcp {

class SwingTrajectory {
 public:
  SwingTrajectory() = default;

  /// Plans the swing from start_W (normal start_normal) to target_W (normal target_normal),
  /// world frame [m]. With a terrain, the apex is raised until the foot (a sphere of radius
  /// foot_radius_m above its contact point) stays terrain_clearance_m above the terrain over the
  /// middle of the path and never enters it elsewhere, up to a rise of 0.3 m.
  static SwingTrajectory Plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& start_normal,
                              const Eigen::Vector3d& target_W, const Eigen::Vector3d& target_normal,
                              const TriangleMesh* terrain, double foot_radius_m, const SwingConfig& config);

  double Duration() const { return duration_s_; }
  /// Phase in [0, 1] after t [s] of swing.
  double Phase(double t) const;
  /// Contact point position and velocity after t [s] of swing (held at the end after Duration()).
  Eigen::Vector3d Position(double t) const;
  Eigen::Vector3d Velocity(double t) const;

  /// Least height of the path above the terrain over the middle of the swing [m] (+inf without terrain).
  double Clearance() const { return clearance_m_; }
  const std::array<Eigen::Vector3d, 4>& ControlPoints() const { return points_; }

 private:
  Eigen::Vector3d Bezier(double s) const;
  Eigen::Vector3d BezierDerivative(double s) const;

  std::array<Eigen::Vector3d, 4> points_{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                         Eigen::Vector3d::Zero()};
  double duration_s_ = 1.0;
  double clearance_m_ = 0.0;
};

}  // namespace rbcp
