#pragma once
/// Shared fixtures of the simulator tests: the shipped robot and physics, flat and tilted ground,
/// a joint PD hold of the reference configuration.

#include <cmath>
#include <string>
#include <vector>

#include "rbcp/core/pose.h"
#include "rbcp/core/yaml_reader.h"
#include "rbcp/robot/robot_model.h"
#include "rbcp/scenario/scenario.h"
#include "rbcp/sim/bullet_world.h"

namespace rbcp::sim::test {

inline std::string ConfigDir() { return std::string(RBCP_SOURCE_DIR) + "/config"; }

inline const RobotModel& Model() {
  static const RobotModel model = RobotModel::LoadDefault(ConfigDir());
  return model;
}

inline PhysicsConfig ShippedPhysics() {
  return PhysicsConfig::Load(YamlMap::LoadFile(ConfigDir() + "/sim.yaml").Map("physics"));
}

/// A 5 x 3 m floor, top at z = 0 (a shorter flat_ground).
inline std::vector<TerrainElement> FlatGround() {
  TerrainBox floor;
  floor.size = Eigen::Vector3d(5.0, 3.0, 0.5);
  floor.position = Eigen::Vector3d(0.75, 0.0, -0.25);
  return {floor};
}

/// A 6 x 3 m plane tilted by `pitch` about world y, its top surface through the origin.
inline std::vector<TerrainElement> Incline(double pitch) {
  TerrainBox slope;
  slope.size = Eigen::Vector3d(6.0, 3.0, 0.5);
  slope.rpy = Eigen::Vector3d(0.0, pitch, 0.0);
  slope.position = -0.25 * (RotationFromRpy(slope.rpy) * Eigen::Vector3d::UnitZ());
  return {slope};
}

/// Joint PD towards q_target, no feed-forward.
inline JointVector PdTorques(const RobotState& s, const JointVector& q_target, double kp = 200.0, double kd = 5.0) {
  return kp * (q_target - s.q) - kd * s.qd;
}

/// Runs `steps` steps, commanding the PD hold of the reference configuration before each.
inline void RunPdHold(BulletWorld& world, int steps) {
  for (int k = 0; k < steps; ++k) {
    world.SetJointTorques(PdTorques(world.State(), Model().ReferenceConfiguration()));
    world.Step();
  }
}

inline int StepsFor(const BulletWorld& world, double seconds) {
  return static_cast<int>(std::lround(seconds / world.Config().time_step_s));
}

}  // namespace rbcp::sim::test
