#pragma once
/// Scripted changes of the world while the robot walks (anymal_sim --events FILE): the world is
/// the simulator's, so it is the one to change it, as the real world changes under a robot.
///
/// The file is YAML, simulated time in seconds, world frame, metres, newtons:
/// @code
/// events:
///   - {t: 6.0, add_box: {name: crate, size: [0.3, 0.3, 0.1], position: [0.8, 0.0, 0.05], rpy: [0, 0, 0]}}
///   - {t: 20.0, remove_box: crate}
///   - {t: 9.0, push: {force: [0, 60, 0], duration: 0.3}}   # on the base, world frame
///   - {t: 12.0, goal: {position: [1.5, 0.4], yaw: 0.0}}
/// @endcode
/// Every event has `t` and exactly one of add_box, remove_box, push or goal; every key is required
/// and no other is accepted. Events happen in time order (equal times in file order).

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "rbcp/scenario/scenario.h"

namespace rbcp::sim {

struct WorldEvent {
  enum class Kind { kAddBox, kRemoveBox, kPush, kGoal };
  double t = 0.0;  ///< simulated time [s]
  Kind kind = Kind::kAddBox;
  std::string name;                                  ///< add_box, remove_box: the box's name
  TerrainBox box;                                    ///< add_box
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();  ///< push [N], world frame, on the base
  double duration_s = 0.0;                           ///< push [s]
  BaseGoal goal;                                     ///< goal: a new goal for the planners
  /// "add box 'crate' (0.3 x 0.3 x 0.1 m at 0.8, 0, 0.05)", "push of 60 N for 0.3 s", ...
  std::string Describe() const;
};

/// Bounds of an events file, checked at load: a file beyond them is an error, not a slow world.
struct WorldEventLimits {
  static constexpr std::size_t kMaxEvents = 1000;
  static constexpr std::size_t kMaxBoxes = 200;         ///< boxes of the events in the world at once
  static constexpr double kMaxTime_s = 1e6;             ///< [s] of simulated time
  static constexpr double kMaxDistance_m = 1000.0;      ///< [m] of a box or a goal from the origin
  static constexpr double kMaxBoxSize_m = 50.0;         ///< [m] of a box side
  static constexpr double kMaxPush_N = 2000.0;          ///< [N] about seven times the robot's weight
  static constexpr double kMaxPushDuration_s = 10.0;    ///< [s]
};

/// Reads an events file. Throws InputError naming the file, the event and the problem: out of the
/// WorldEventLimits, a box added twice, or removed when it is not in the world.
std::vector<WorldEvent> LoadWorldEvents(const std::string& path);
/// Same, from text; `where` names it in errors.
std::vector<WorldEvent> ParseWorldEvents(const std::string& yaml_text, const std::string& where);

}  // namespace rbcp::sim
