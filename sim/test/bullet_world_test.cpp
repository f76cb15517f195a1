#include "rbcp/sim/bullet_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>

#include "rbcp/core/pose.h"
#include "sim_test_util.h"

namespace rbcp::sim {
namespace {

using test::Model;

// Sum of the URDF's link masses [kg]: the trunk and four legs of hip, thigh, shank, adapter and
// foot (30.42 kg rounded).
constexpr double kUrdfMass = 16.793507758 + 4 * (1.42462064 + 1.634976467 + 0.207204302 + 0.140170767 + 0.001);

/// The robot's foot sphere centre in its FOOT link frame, from the URDF's collision origin.
Eigen::Vector3d SphereCentreInFoot(Leg leg) {
  const std::string foot = std::string(LegName(leg)) + "_FOOT";
  for (const CollisionShape& s : Model().CollisionShapes()) {
    if (s.link == foot && s.kind == CollisionShape::Kind::kSphere) return s.pose_link.translation();
  }
  ADD_FAILURE() << "no sphere on " << foot;
  return Eigen::Vector3d::Zero();
}

/// Standing start on flat ground: reference configuration, feet `clearance` above the floor.
void ResetStanding(BulletWorld& world, double clearance = 0.01) {
  world.ResetRobot(Eigen::Vector3d(0, 0, Model().NominalBaseHeight() + clearance), Eigen::Quaterniond::Identity(),
                   Model().ReferenceConfiguration());
}

TEST(BulletWorld, MassAsBuiltIsTheUrdfs) {
  const BulletWorld world(test::Model(), test::FlatGround(), test::ShippedPhysics());
  EXPECT_NEAR(world.RobotMass(), kUrdfMass, 1e-9);
  EXPECT_NEAR(world.RobotMass(), 30.42, 0.01);
  EXPECT_NEAR(world.RobotMass(), Model().TotalMass(), 1e-9);
}

TEST(BulletWorld, StartsAtRestInTheReferenceConfigurationOneMetreUp) {
  const BulletWorld world(test::Model(), test::FlatGround(), test::ShippedPhysics());
  const RobotState s = world.State();
  EXPECT_EQ(s.t, 0.0);
  EXPECT_NEAR((s.base_position_W - Eigen::Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.base_orientation_W.angularDistance(Eigen::Quaterniond::Identity()), 0.0, 1e-12);
  EXPECT_TRUE(s.q == Model().ReferenceConfiguration());
  EXPECT_TRUE(s.qd.isZero());
  EXPECT_TRUE(s.tau.isZero());
}

TEST(BulletWorld, KinematicsAgreeWithThePlanningModel) {
  BulletWorld world(test::Model(), test::FlatGround(), test::ShippedPhysics());
  JointVector q_bent = Model().ReferenceConfiguration();
  q_bent << 0.3, 1.1, -1.9, -0.2, 0.4, -0.6, 0.5, -1.2, 2.0, -0.4, -0.3, 0.7;
  JointVector q_odd = JointVector::Zero();
  q_odd << -0.8, -0.5, 0.9, 0.7, 2.0, -2.3, -0.1, 0.2, -0.4, 0.9, 1.5, 2.8;
  const std::vector<JointVector> qs = {Model().ReferenceConfiguration(), JointVector::Zero(), q_bent, q_odd};
  const std::vector<Eigen::Isometry3d> bases = {
      Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.6)),
      Eigen::Translation3d(1.2, -0.7, 2.5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()),
      Eigen::Translation3d(-3.0, 4.0, 1.0) * Eigen::AngleAxisd(2.9, Eigen::Vector3d(-0.2, 0.9, 0.1).normalized())};
  for (const Eigen::Isometry3d& base : bases) {
    for (const JointVector& q : qs) {
      world.ResetRobot(base.translation(), Eigen::Quaterniond(base.linear()), q);
      const RobotState s = world.State();
      EXPECT_TRUE(s.q == q);
      EXPECT_TRUE(s.qd.isZero());
      EXPECT_NEAR((s.base_position_W - base.translation()).norm(), 0.0, 1e-12);
      EXPECT_NEAR(s.base_orientation_W.angularDistance(Eigen::Quaterniond(base.linear())), 0.0, 1e-12);
      const std::vector<Eigen::Isometry3d> links = Model().LinkPoses(q);
      const auto centres = world.FootCentersW();
      for (Leg leg : kAllLegs) {
        const int foot = Model().LinkIndex(std::string(LegName(leg)) + "_FOOT");
        const Eigen::Vector3d expected = base * (links[static_cast<std::size_t>(foot)] * SphereCentreInFoot(leg));
        EXPECT_NEAR((centres[static_cast<std::size_t>(Index(leg))] - expected).norm(), 0.0, 1e-9) << LegName(leg);
        // The planners' contact point lies on the sphere, straight below its centre along the shank.
        const Eigen::Vector3d contact = base * Model().FootPosition(leg, LegJoints(q, leg));
        EXPECT_NEAR((contact - expected).norm(), Model().FootRadius(), 1e-9) << LegName(leg);
      }
    }
  }
}

TEST(BulletWorld, TimeStepIsExactlyTheConfiguredOne) {
  BulletWorld world(test::Model(), test::FlatGround(), test::ShippedPhysics());
  const double dt = world.Config().time_step_s;
  const double g = world.Config().gravity_mps2;
  // Free fall from rest: Bullet's semi-implicit Euler with step dt gives v_n = -g n dt and
  // z_n = z0 - g dt^2 n (n + 1) / 2 exactly; Bullet's default (1/60 s substeps, interpolated
  // poses in between) would not.
  const double z0 = world.State().base_position_W.z();
  const int n = 120;
  for (int k = 0; k < n; ++k) world.Step();
  EXPECT_DOUBLE_EQ(world.Time(), n * dt);
  const RobotState s = world.State();
  EXPECT_NEAR(s.base_linear_velocity_W.z(), -g * n * dt, 1e-9);
  EXPECT_NEAR(s.base_position_W.z(), z0 - 0.5 * g * dt * dt * n * (n + 1), 1e-9);
  EXPECT_NEAR(s.base_linear_velocity_W.head<2>().norm(), 0.0, 1e-9);
  EXPECT_TRUE(world.TerrainContacts().empty());
  // Primitives that overlap by construction (the thigh's upper protector around the HAA
  // actuator) are not self-contacts.
  const auto self = world.SelfContacts();
  EXPECT_TRUE(self.empty()) << self.front().first << " / " << self.front().second;
}

TEST(BulletWorld, WithoutTorquesTheRobotCollapses) {
  const Scenario flat = LoadScenario(test::ConfigDir() + "/scenarios/flat_ground.yaml");
  BulletWorld world(test::Model(), flat.terrain, test::ShippedPhysics());
  ResetStanding(world);
  std::set<std::string> touching;
  for (int k = 0; k < test::StepsFor(world, 2.0); ++k) {
    world.Step();
    for (const TerrainContact& c : world.TerrainContacts()) {
      if (!c.is_foot) touching.insert(c.link);
    }
  }
  const RobotState s = world.State();
  EXPECT_LT(s.base_position_W.z(), 0.25);
  EXPECT_FALSE(touching.empty());
  std::string links;
  for (const std::string& l : touching) links += l + " ";
  std::printf("collapsed: base z %.3f m, non-foot links on the ground: %s\n", s.base_position_W.z(), links.c_str());
}

TEST(BulletWorld, AJointPdHoldKeepsItStanding) {
  BulletWorld world(test::Model(), test::FlatGround(), test::ShippedPhysics());
  ResetStanding(world);
  test::RunPdHold(world, test::StepsFor(world, 2.0));
  const RobotState s = world.State();
  const double weight = world.RobotMass() * world.Config().gravity_mps2;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (Leg leg : kAllLegs) {
    EXPECT_TRUE(s.foot_contact[static_cast<std::size_t>(Index(leg))]) << LegName(leg);
    total += s.foot_force_W[static_cast<std::size_t>(Index(leg))];
  }
  EXPECT_NEAR(s.base_position_W.z(), Model().NominalBaseHeight(), 0.04);
  EXPECT_NEAR(total.z(), weight, 0.03 * weight);
  EXPECT_LT(total.head<2>().norm(), 0.03 * weight);
  EXPECT_LT(s.base_linear_velocity_W.norm(), 0.01);
  double deepest = 0.0;
  std::set<std::string> feet;
  for (const TerrainContact& c : world.TerrainContacts()) {
    EXPECT_TRUE(c.is_foot) << c.link;
    ASSERT_TRUE(c.leg.has_value());
    EXPECT_EQ(c.link, std::string(LegName(*c.leg)) + "_FOOT");
    EXPECT_NEAR((c.normal_W - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-9);
    EXPECT_NEAR(c.position_W.z(), 0.0, 0.002);
    EXPECT_GT(c.normal_force_N, 0.0);
    feet.insert(c.link);
    deepest = std::max(deepest, c.penetration_m);
  }
  EXPECT_EQ(feet.size(), 4u);
  EXPECT_LT(deepest, 0.002);
  EXPECT_TRUE(world.SelfContacts().empty());
  // The foot spheres rest on the floor.
  for (const Eigen::Vector3d& c : world.FootCentersW()) EXPECT_NEAR(c.z(), Model().FootRadius(), 0.002);
  std::printf("standing: base z %.4f m (nominal %.4f), sum Fz %.2f N (m g %.2f), lateral %.3f N, deepest %.2e m\n",
              s.base_position_W.z(), Model().NominalBaseHeight(), total.z(), weight, total.head<2>().norm(), deepest);
  for (Leg leg : kAllLegs) {
    const auto& f = s.foot_force_W[static_cast<std::size_t>(Index(leg))];
    std::printf("  %s force (%.2f %.2f %.2f) N, tau (%.2f %.2f %.2f)\n", std::string(LegName(leg)).c_str(), f.x(), f.y(),
                f.z(), s.tau[3 * Index(leg)], s.tau[3 * Index(leg) + 1], s.tau[3 * Index(leg) + 2]);
  }
}

TEST(BulletWorld, StandsOnATriangleMeshFloor) {
  // The flat floor as a mesh file (a closed 5 x 3 x 0.5 m box, top at z = 0).
  const std::string path = ::testing::TempDir() + "rbcp_sim_floor.obj";
  {
    TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(5.0, 3.0, 0.5));
    std::ofstream out(path);
    for (const Eigen::Vector3d& v : box.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& t : box.triangles) out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  }
  TerrainMeshFile mesh;
  mesh.file = path;
  mesh.resolved_path = path;
  mesh.position = Eigen::Vector3d(0.75, 0.0, -0.25);
  BulletWorld world(test::Model(), {mesh}, test::ShippedPhysics());
  ResetStanding(world);
  test::RunPdHold(world, test::StepsFor(world, 1.5));
  const RobotState s = world.State();
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (Leg leg : kAllLegs) {
    EXPECT_TRUE(s.foot_contact[static_cast<std::size_t>(Index(leg))]) << LegName(leg);
    total += s.foot_force_W[static_cast<std::size_t>(Index(leg))];
  }
  const double weight = world.RobotMass() * world.Config().gravity_mps2;
  EXPECT_NEAR(total.z(), weight, 0.03 * weight);
  EXPECT_NEAR(s.base_position_W.z(), Model().NominalBaseHeight(), 0.04);
  for (const Eigen::Vector3d& c : world.FootCentersW()) EXPECT_NEAR(c.z(), Model().FootRadius(), 0.002);
  std::remove(path.c_str());
}

TEST(BulletWorld, CrossedLegsAreSelfContacts) {
  // In the air, the fore legs swung under the trunk towards each other until they cross.
  BulletWorld world(test::Model(), {}, test::ShippedPhysics());
  JointVector q = Model().ReferenceConfiguration();
  q[0] = -0.9;  // LF_HAA: foot towards -y
  q[3] = 0.9;   // RF_HAA: foot towards +y
  world.ResetRobot(Eigen::Vector3d(0, 0, 3), Eigen::Quaterniond::Identity(), q);
  world.Step();
  bool fore_legs = false;
  for (const auto& [a, b] : world.SelfContacts()) {
    fore_legs = fore_legs || (a.substr(0, 2) == "LF" && b.substr(0, 2) == "RF") || (a.substr(0, 2) == "RF" && b.substr(0, 2) == "LF");
  }
  EXPECT_TRUE(fore_legs);
}

TEST(BulletWorld, TorquesSaturateAtTheCommandLimit) {
  BulletWorld world(test::Model(), test::FlatGround(), test::ShippedPhysics());
  JointVector command = JointVector::Constant(100.0);
  command[4] = -100.0;
  command[7] = 12.5;
  const JointVector applied = world.SetJointTorques(command);
  for (int i = 0; i < kNumJoints; ++i) {
    const double expected = i == 4 ? -40.0 : (i == 7 ? 12.5 : 40.0);
    EXPECT_EQ(applied[i], expected) << JointName(i);
  }
  world.Step();
  EXPECT_TRUE(world.State().tau == applied);
}

TEST(BulletWorld, TorqueIsCutAtTheSpeedLimit) {
  // In the air, the other joints held by a PD, a full torque on LF_KFE spins the knee up; from
  // 15 rad/s on the accelerating torque is cut to zero (checked in every step), a braking
  // torque is delivered in full.
  BulletWorld world(test::Model(), {}, test::ShippedPhysics());
  world.ResetRobot(Eigen::Vector3d(0, 0, 5), Eigen::Quaterniond::Identity(), Model().ReferenceConfiguration());
  const int knee = 2;
  const double limit = Model().JointVelocityLimit();
  double peak = 0.0;
  int cut_steps = 0;
  for (int k = 0; k < test::StepsFor(world, 0.2); ++k) {
    const RobotState s = world.State();
    JointVector command = test::PdTorques(s, Model().ReferenceConfiguration(), 400.0, 10.0);
    command[knee] = 40.0;
    const JointVector applied = world.SetJointTorques(command);
    EXPECT_EQ(applied[knee], s.qd[knee] >= limit ? 0.0 : 40.0) << "qd " << s.qd[knee];
    world.Step();
    EXPECT_TRUE(world.State().tau == applied);
    peak = std::max(peak, s.qd[knee]);
    if (applied[knee] == 0.0) ++cut_steps;
  }
  EXPECT_GT(cut_steps, 10);
  EXPECT_GE(peak, limit);
  // Without the cut the knee would reach Bullet's velocity clamp (60 rad/s) within 0.02 s; with
  // it the speed only overshoots by what the leg's dynamic coupling adds at zero knee torque.
  EXPECT_LT(peak, limit + 5.0);
  JointVector brake = JointVector::Zero();
  brake[knee] = -40.0;
  ASSERT_GE(world.State().qd[knee], limit - 1.0);
  EXPECT_EQ(world.SetJointTorques(brake)[knee], -40.0);
  world.Step();
  EXPECT_EQ(world.State().tau[knee], -40.0);
}

TEST(BulletWorld, JointsStopAtTheUrdfLimits) {
  // LF_KFE folded to 9.3 rad (its URDF range is +-9.42) in the air, pushed on by the full torque.
  for (const double sign : {1.0, -1.0}) {
    BulletWorld world(test::Model(), {}, test::ShippedPhysics());
    JointVector q = Model().ReferenceConfiguration();
    q[2] = sign * 9.3;
    world.ResetRobot(Eigen::Vector3d(0, 0, 5), Eigen::Quaterniond::Identity(), q);
    double reach = 0.0;
    for (int k = 0; k < test::StepsFor(world, 0.5); ++k) {
      JointVector command = test::PdTorques(world.State(), q, 400.0, 10.0);
      command[2] = sign * 40.0;
      world.SetJointTorques(command);
      world.Step();
      reach = std::max(reach, sign * world.State().q[2]);
    }
    EXPECT_LT(reach, 9.42 + 0.02) << sign;
    EXPECT_NEAR(sign * world.State().q[2], 9.42, 1e-3) << sign;
  }
}

TEST(BulletWorld, ActuatorTorqueModel) {
  EXPECT_EQ(ActuatorTorque(100.0, 0.0, 40.0, 15.0), 40.0);
  EXPECT_EQ(ActuatorTorque(-100.0, 3.0, 40.0, 15.0), -40.0);
  EXPECT_EQ(ActuatorTorque(10.0, 14.9, 40.0, 15.0), 10.0);
  EXPECT_EQ(ActuatorTorque(10.0, 15.0, 40.0, 15.0), 0.0);   // would speed it up further
  EXPECT_EQ(ActuatorTorque(-10.0, -16.0, 40.0, 15.0), 0.0);
  EXPECT_EQ(ActuatorTorque(-10.0, 16.0, 40.0, 15.0), -10.0);  // brakes
  EXPECT_EQ(ActuatorTorque(50.0, -20.0, 40.0, 15.0), 40.0);
}

bool BitIdentical(const RobotState& a, const RobotState& b) {
  const auto same = [](const auto& x, const auto& y) { return std::memcmp(x.data(), y.data(), sizeof(double) * x.size()) == 0; };
  bool equal = a.t == b.t && same(a.base_position_W, b.base_position_W) &&
               same(a.base_orientation_W.coeffs(), b.base_orientation_W.coeffs()) &&
               same(a.base_linear_velocity_W, b.base_linear_velocity_W) &&
               same(a.base_angular_velocity_B, b.base_angular_velocity_B) && same(a.q, b.q) && same(a.qd, b.qd) &&
               same(a.tau, b.tau) && a.foot_contact == b.foot_contact;
  for (std::size_t l = 0; l < static_cast<std::size_t>(kNumLegs); ++l) equal = equal && same(a.foot_force_W[l], b.foot_force_W[l]);
  return equal;
}

TEST(BulletWorld, IdenticalRunsGiveBitIdenticalStates) {
  BulletWorld a(test::Model(), test::FlatGround(), test::ShippedPhysics());
  BulletWorld b(test::Model(), test::FlatGround(), test::ShippedPhysics());
  ResetStanding(a, 0.03);
  ResetStanding(b, 0.03);
  // Interleaved, so that any shared state between worlds would show.
  const int steps = test::StepsFor(a, 1.0);
  for (int k = 0; k < steps; ++k) {
    JointVector q_target = Model().ReferenceConfiguration();
    q_target[1] += 0.3 * std::sin(8.0 * a.Time());  // a swinging LF_HFE: changing contacts
    a.SetJointTorques(test::PdTorques(a.State(), q_target));
    b.SetJointTorques(test::PdTorques(b.State(), q_target));
    a.Step();
    b.Step();
  }
  EXPECT_TRUE(BitIdentical(a.State(), b.State()));
  EXPECT_EQ(a.TerrainContacts().size(), b.TerrainContacts().size());
}

struct InclineRun {
  double max_foot_displacement = 0.0;  ///< largest foot centre displacement, 0.5 s to 1.5 s [m]
  double base_displacement = 0.0;      ///< base displacement over the same second [m]
  double max_friction_ratio = 0.0;     ///< same second: largest |tangential| / normal force of a foot loaded > 20 N
  /// Same second, per foot: the median of that ratio; the largest of the feet loaded in >= 50 steps.
  double max_median_friction_ratio = 0.0;
};

/// Stands the robot on an incline of `pitch` (facing downhill, base parallel to the slope) and
/// holds the reference configuration with a joint PD for 1.5 s.
InclineRun StandOnIncline(double pitch) {
  BulletWorld world(test::Model(), test::Incline(pitch), test::ShippedPhysics());
  const Eigen::Matrix3d R = RotationFromRpy(Eigen::Vector3d(0.0, pitch, 0.0));
  world.ResetRobot(R * Eigen::Vector3d(0, 0, Model().NominalBaseHeight() + 0.005), Eigen::Quaterniond(R),
                   Model().ReferenceConfiguration());
  test::RunPdHold(world, test::StepsFor(world, 0.5));  // lands and settles
  const auto feet0 = world.FootCentersW();
  const Eigen::Vector3d base0 = world.State().base_position_W;
  InclineRun run;
  std::array<std::vector<double>, kNumLegs> ratios;
  for (int k = 0; k < test::StepsFor(world, 1.0); ++k) {
    test::RunPdHold(world, 1);
    const RobotState s = world.State();
    for (std::size_t l = 0; l < ratios.size(); ++l) {
      const Eigen::Vector3d f = R.transpose() * s.foot_force_W[l];  // slope frame: z along the normal
      if (f.z() > 20.0) ratios[l].push_back(f.head<2>().norm() / f.z());
    }
  }
  const auto feet1 = world.FootCentersW();
  for (std::size_t l = 0; l < feet0.size(); ++l) {
    run.max_foot_displacement = std::max(run.max_foot_displacement, (feet1[l] - feet0[l]).norm());
    std::vector<double>& r = ratios[l];
    if (r.empty()) continue;
    std::sort(r.begin(), r.end());
    run.max_friction_ratio = std::max(run.max_friction_ratio, r.back());
    if (r.size() >= 50) run.max_median_friction_ratio = std::max(run.max_median_friction_ratio, r[r.size() / 2]);
  }
  run.base_displacement = (world.State().base_position_W - base0).norm();
  std::printf("incline %.0f deg: feet moved <= %.4f m, base %.4f m in 1 s; foot |T|/N: max %.3f, largest median %.3f\n",
              pitch * 180 / M_PI, run.max_foot_displacement, run.base_displacement, run.max_friction_ratio,
              run.max_median_friction_ratio);
  return run;
}

TEST(BulletWorld, FeetStickOnA20DegreeIncline) {
  // tan 20 deg = 0.36 < 0.8: the feet stay put, well inside their friction cones. (On 30 degrees the PD-held reference stance puts ~85 % of the
  // normal load on the downhill legs, the unloaded uphill feet need more than 0.8 and slip:
  // a property of that stance and controller, not of the friction model.)
  const InclineRun run = StandOnIncline(20.0 * M_PI / 180.0);
  EXPECT_LT(run.max_foot_displacement, 0.005);
  EXPECT_LT(run.base_displacement, 0.02);
  EXPECT_LT(run.max_friction_ratio, 0.7);
}

TEST(BulletWorld, FeetSlideOnA45DegreeInclineWithTheConfiguredFriction) {
  // tan 45 deg = 1 > 0.8: the robot slides. A loaded, sliding foot's force lies on the edge of
  // the friction pyramid of the combined coefficient 0.8 (robot 0.8 x terrain 1; Bullet's default
  // 0.5 x 0.5 would give 0.25): 0.8 along the sliding direction, plus what the cross direction
  // (bounded by 0.8 N as well) adds when the foot also slides sideways.
  const InclineRun run = StandOnIncline(45.0 * M_PI / 180.0);
  EXPECT_GT(run.base_displacement, 0.5);
  EXPECT_GT(run.max_foot_displacement, 0.5);
  EXPECT_GT(run.max_median_friction_ratio, 0.8 * 0.98);
  EXPECT_LT(run.max_median_friction_ratio, 0.8 * 1.08);
}

}  // namespace
}  // namespace rbcp::sim
