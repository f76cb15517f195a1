#pragma once
/// A contact plan: whole-body states one step apart. Between consecutive states exactly one leg
/// (moving_leg of the later state) changes its contact; the other three stay where they are.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "rbcp/core/leg.h"

namespace rbcp {

/// A foot in contact: the contact point on the surface and the surface normal, world frame.
struct FootContact {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();   ///< unit
};

struct WholeBodyState {
  Eigen::Vector3d base_position = Eigen::Vector3d::Zero();  ///< [m], world frame
  Eigen::Vector3d base_rpy = Eigen::Vector3d::Zero();       ///< roll, pitch, yaw [rad], base to world (Rz Ry Rx)
  Eigen::Matrix<double, 12, 1> joints = Eigen::Matrix<double, 12, 1>::Zero();  ///< [rad], LF, RF, LH, RH x (HAA, HFE, KFE)
  std::array<FootContact, kNumLegs> feet{};                 ///< indexed by Index(Leg)
  int moving_leg = -1;  ///< Index(Leg) of the leg that stepped to reach this state; -1 for the first state
  /// The swing path of moving_leg that reached this state, as the planner checked it
  /// (SwingTrajectory::Given): the apex height [m, world z] and the path's sideways bow at the
  /// apex [m, world xy]. NaN apex: no path planned (the controller plans one by the stance rules).
  double swing_apex_z = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector2d swing_bow = Eigen::Vector2d::Zero();
  bool HasSwing() const { return std::isfinite(swing_apex_z); }
  /// This state as the first of a plan: no leg stepped to reach it, so no swing either.
  void MarkAsStart() {
    moving_leg = -1;
    swing_apex_z = std::numeric_limits<double>::quiet_NaN();
    swing_bow.setZero();
  }
};

struct ContactPlan {
  std::vector<WholeBodyState> states;  ///< from the start state to the goal state
  /// The last state stands at the goal; false for a receding-horizon piece that stops short of it.
  bool reaches_goal = true;
};

}  // namespace rbcp
