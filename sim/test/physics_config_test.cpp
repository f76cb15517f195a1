#include <gtest/gtest.h>

#include "rbcp/sim/bullet_world.h"
#include "rbcp/test_support/error_of.h"
#include "sim_test_util.h"

namespace rbcp::sim {
namespace {

using rbcp::test_support::ErrorOf;

constexpr const char* kValid =
    "{gravity_mps2: 9.8, time_step_s: 0.0005, solver_iterations: 40, friction: 0.7}";

std::string ErrorWith(const char* key, const char* value) {
  YAML::Node node = YAML::Load(kValid);
  node[key] = YAML::Load(value);
  return ErrorOf([&] { PhysicsConfig::Load(YamlMap(node, "sim.yaml: physics")); });
}

TEST(PhysicsConfig, LoadsTheShippedFile) {
  const PhysicsConfig c = test::ShippedPhysics();
  EXPECT_DOUBLE_EQ(c.gravity_mps2, 9.81);
  EXPECT_NEAR(c.time_step_s, 1.0 / 1200.0, 1e-15);
  EXPECT_GE(c.solver_iterations, 1);
  EXPECT_DOUBLE_EQ(c.friction, 0.8);
}

TEST(PhysicsConfig, ReadsEveryKey) {
  const PhysicsConfig c = PhysicsConfig::Load(YamlMap(YAML::Load(kValid), "p"));
  EXPECT_DOUBLE_EQ(c.gravity_mps2, 9.8);
  EXPECT_DOUBLE_EQ(c.time_step_s, 0.0005);
  EXPECT_EQ(c.solver_iterations, 40);
  EXPECT_DOUBLE_EQ(c.friction, 0.7);
}

TEST(PhysicsConfig, RejectsMissingAndUnknownKeys) {
  EXPECT_EQ(ErrorOf([] {
              YAML::Node node = YAML::Load(kValid);
              node.remove("friction");
              PhysicsConfig::Load(YamlMap(node, "sim.yaml: physics"));
            }),
            "sim.yaml: physics: 'friction': missing key");
  EXPECT_EQ(ErrorOf([] {
              YAML::Node node = YAML::Load(kValid);
              node["damping"] = 0.1;
              PhysicsConfig::Load(YamlMap(node, "sim.yaml: physics"));
            }),
            "sim.yaml: physics: 'damping': unknown key");
  // The robot's limits are the robot model's (config/robots/anymal_b.yaml), not the simulator's.
  EXPECT_EQ(ErrorWith("torque_limit_Nm", "40"), "sim.yaml: physics: 'torque_limit_Nm': unknown key");
}

TEST(PhysicsConfig, RejectsOutOfRangeValues) {
  EXPECT_EQ(ErrorWith("time_step_s", "0.002"), "sim.yaml: physics: 'time_step_s': expected a number in (0, 0.001] [s], got 0.002");
  EXPECT_EQ(ErrorWith("time_step_s", "0"), "sim.yaml: physics: 'time_step_s': expected a number in (0, 0.001] [s], got 0");
  EXPECT_EQ(ErrorWith("time_step_s", "0.001"), "");
  EXPECT_EQ(ErrorWith("solver_iterations", "0"), "sim.yaml: physics: 'solver_iterations': expected an integer >= 1, got 0");
  EXPECT_EQ(ErrorWith("friction", "0"), "sim.yaml: physics: 'friction': expected a positive number, got 0");
  EXPECT_EQ(ErrorWith("gravity_mps2", "-9.81"),
            "sim.yaml: physics: 'gravity_mps2': expected a non-negative number [m/s^2], got -9.81");
  EXPECT_EQ(ErrorWith("gravity_mps2", "0"), "");
  EXPECT_EQ(ErrorWith("gravity_mps2", ".nan"), "sim.yaml: physics: 'gravity_mps2': expected a finite number, got .nan");
}

TEST(PhysicsConfig, TheWorldRejectsAnInvalidConfig) {
  PhysicsConfig c;
  c.time_step_s = 0.002;
  EXPECT_EQ(ErrorOf([&] { BulletWorld(test::Model(), test::FlatGround(), c); }),
            "PhysicsConfig: 'time_step_s': expected a number in (0, 0.001] [s], got 0.002");
}

}  // namespace
}  // namespace rbcp::sim
