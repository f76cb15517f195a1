#pragma once
/// A contact plan: whole-body states one step apart. Between consecutive states exactly one leg
/// (moving_leg of the later state) changes its contact; the other three stay where they are.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
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
  /// When the dynamic walk lifts moving_leg off and puts it down to reach this state [s from the
  /// plan's start] (TimeDynamicWalk, stance/dynamic_walk.h): the timing the planner checked the step
  /// with. NaN: untimed (the first state, or a plan without timing, which the controller times by
  /// the same rules).
  double lift_off_s = std::numeric_limits<double>::quiet_NaN();
  double touch_down_s = std::numeric_limits<double>::quiet_NaN();
  bool HasTiming() const { return std::isfinite(lift_off_s) && std::isfinite(touch_down_s); }
  /// This state as the first of a plan: no leg stepped to reach it, so no swing and no timing.
  void MarkAsStart() {
    moving_leg = -1;
    swing_apex_z = std::numeric_limits<double>::quiet_NaN();
    swing_bow.setZero();
    ClearTiming();
  }
  void ClearTiming() {
    lift_off_s = std::numeric_limits<double>::quiet_NaN();
    touch_down_s = std::numeric_limits<double>::quiet_NaN();
  }
};

struct ContactPlan {
  std::vector<WholeBodyState> states;  ///< from the start state to the goal state
  /// The last state stands at the goal; false for a receding-horizon piece that stops short of it.
  bool reaches_goal = true;
  /// Every step (states 1..n) carries its timing.
  bool Timed() const {
    if (states.size() < 2) return false;
    for (std::size_t i = 1; i < states.size(); ++i) {
      if (!states[i].HasTiming()) return false;
    }
    return true;
  }
  /// Drops every step's timing (a plan whose steps changed).
  void ClearTiming() {
    for (WholeBodyState& s : states) s.ClearTiming();
  }
};

/// What is wrong with a plan's timing, if anything: each step timed or none; the first state
/// untimed; every step's lift-off at or after the previous touch-down (the first at or after 0)
/// and before its own touch-down, all within a day.
std::optional<std::string> TimingProblem(const ContactPlan& plan);

}  // namespace rbcp
