#include "rbcp/robot/robot_model.h"

#include <gtest/gtest.h>

#include <map>
#include <Eigen/Eigenvalues>
#include <random>
#include <set>

#include "robot_test_util.h"

namespace rbcp {
namespace {

using test::Anymal;

JointVector Uniform(const Eigen::Vector3d& per_leg_fore_left) {
  // Mirror one LF triple onto the four legs: right legs negate HAA, hind legs negate HFE and KFE.
  JointVector q;
  for (Leg leg : kAllLegs) {
    Eigen::Vector3d ql = per_leg_fore_left;
    ql[0] *= LeftSign(leg);
    ql[1] *= ForeSign(leg);
    ql[2] *= ForeSign(leg);
    SetLegJoints(q, leg, ql);
  }
  return q;
}

Eigen::Vector3d Mirror(const Eigen::Vector3d& p_lf, Leg leg) {
  return Eigen::Vector3d(ForeSign(leg) * p_lf.x(), LeftSign(leg) * p_lf.y(), p_lf.z());
}

TEST(RobotModel, TotalMassMatchesTheDescription) {
  EXPECT_NEAR(Anymal().TotalMass(), 30.42, 0.05);
  double sum = 0.0;
  for (const RobotLink& link : Anymal().Links()) sum += link.mass;
  EXPECT_NEAR(sum, Anymal().TotalMass(), 1e-12);
}

TEST(RobotModel, LinksAreOrderedTrunkThenLegsHipToFoot) {
  const auto& links = Anymal().Links();
  ASSERT_EQ(links.size(), 21u);
  EXPECT_EQ(links[0].name, "base");
  EXPECT_FALSE(links[0].leg.has_value());
  EXPECT_NEAR(links[0].mass, 16.793507758, 1e-12);
  const std::array<std::string, 5> parts = {"HIP", "THIGH", "SHANK", "ADAPTER", "FOOT"};
  for (Leg leg : kAllLegs) {
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const RobotLink& link = links[1 + 5 * static_cast<std::size_t>(Index(leg)) + k];
      EXPECT_EQ(link.name, std::string(LegName(leg)) + "_" + parts[k]);
      ASSERT_TRUE(link.leg.has_value());
      EXPECT_EQ(*link.leg, leg);
    }
  }
  EXPECT_EQ(Anymal().LinkIndex("RH_FOOT"), 20);
  EXPECT_EQ(Anymal().LinkIndex("nope"), -1);
  EXPECT_EQ(JointName(0), "LF_HAA");
  EXPECT_EQ(JointName(5), "RF_KFE");
  EXPECT_EQ(JointName(Leg::kLH, 1), "LH_HFE");
  EXPECT_EQ(JointIndex("RF_KFE"), 5);
  EXPECT_EQ(JointIndex("LF_SHANK_TO_ADAPTER"), -1);
}

TEST(RobotModel, JointsAreTheUrdfTreeBreadthFirst) {
  const auto& joints = Anymal().Joints();
  ASSERT_EQ(joints.size(), 20u);  // 12 leg joints, per leg SHANK_TO_ADAPTER and ADAPTER_TO_FOOT
  std::set<std::string> placed = {"base"};
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const RobotJoint& j = joints[i];
    EXPECT_TRUE(placed.count(j.parent_link)) << j.name << ": parent placed by an earlier joint";
    placed.insert(j.child_link);
    if (i < 4) {
      EXPECT_EQ(j.parent_link, "base");  // the base's children first, in name order
    }
    if (j.type == RobotJoint::Type::kFixed) {
      EXPECT_EQ(j.axis, Eigen::Vector3d::Zero()) << j.name;
      continue;
    }
    EXPECT_EQ(j.type, RobotJoint::Type::kRevolute) << j.name;
    EXPECT_EQ(j.lower_limit, -9.42);
    EXPECT_EQ(j.upper_limit, 9.42);
  }
  EXPECT_EQ(joints[0].name, "LF_HAA");
  EXPECT_EQ(joints[3].name, "RH_HAA");
  EXPECT_EQ(placed.size(), Anymal().Links().size());

  for (const RobotJoint& j : joints) {
    if (j.name == "LF_KFE") {
      EXPECT_EQ(j.parent_link, "LF_THIGH");
      EXPECT_EQ(j.child_link, "LF_SHANK");
      EXPECT_EQ(j.axis, Eigen::Vector3d::UnitY());
      EXPECT_TRUE(j.origin.isApprox(Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.109, -0.25))));
    }
    if (j.name == "RH_ADAPTER_TO_FOOT") {
      EXPECT_EQ(j.parent_link, "RH_ADAPTER");
      EXPECT_EQ(j.child_link, "RH_FOOT");
      EXPECT_TRUE(j.origin.translation().isApprox(Eigen::Vector3d(0.0, 0.0, -0.32125)));
    }
  }
}

TEST(RobotModel, HipPositionsFollowTheSignPattern) {
  for (Leg leg : kAllLegs) {
    EXPECT_TRUE(Anymal().HipPosition(leg).isApprox(Eigen::Vector3d(0.277 * ForeSign(leg), 0.116 * LeftSign(leg), 0.0)))
        << LegName(leg);
  }
}

TEST(RobotModel, ForwardKinematicsMatchesPublishedFootPositions) {
  const RobotModel& m = Anymal();
  const int lf_foot = m.LinkIndex("LF_FOOT");
  ASSERT_GE(lf_foot, 0);

  // q = 0: FOOT frame (0.4405, 0.246, -0.57125); contact point 7.75 mm lower.
  auto poses = m.LinkPoses(JointVector::Zero());
  EXPECT_LT((poses[static_cast<std::size_t>(lf_foot)].translation() - Eigen::Vector3d(0.4405, 0.246, -0.57125)).norm(),
            1e-12);
  for (Leg leg : kAllLegs) {
    EXPECT_LT((m.FootPosition(leg, Eigen::Vector3d::Zero()) - Mirror({0.4405, 0.246, -0.579}, leg)).norm(), 1e-12)
        << LegName(leg);
  }

  // Published derived FOOT frames (anymal_b.md section 7.1), 0.1 mm resolution.
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> cases = {
      {{-0.1, 0.7, -1.0}, {0.3699, 0.1986, -0.4792}},       // ERD "standing"
      {{-0.12, 0.724, -1.082}, {0.3811, 0.1908, -0.4654}},  // RBPRM referenceConfig (HEAD)
      {{0.04, 0.74, -1.08}, {0.3733, 0.2641, -0.4486}},     // RBPRM 2019 symmetric
      {{0.03, 0.4, -0.8}, {0.4604, 0.2606, -0.4831}},       // RaiSim nominal
  };
  for (const auto& [q_lf, foot_lf] : cases) {
    poses = m.LinkPoses(Uniform(q_lf));
    for (Leg leg : kAllLegs) {
      const int foot = m.LinkIndex(std::string(LegName(leg)) + "_FOOT");
      EXPECT_LT((poses[static_cast<std::size_t>(foot)].translation() - Mirror(foot_lf, leg)).norm(), 1.5e-4)
          << LegName(leg) << " q_LF " << q_lf.transpose();
    }
  }
}

TEST(RobotModel, LeftRightAndForeHindMirrorSymmetry) {
  const RobotModel& m = Anymal();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const Eigen::Vector3d p_lf = m.FootPosition(Leg::kLF, q);
    const Eigen::Vector3d p_rf = m.FootPosition(Leg::kRF, Eigen::Vector3d(-q[0], q[1], q[2]));
    const Eigen::Vector3d p_lh = m.FootPosition(Leg::kLH, Eigen::Vector3d(q[0], -q[1], -q[2]));
    const Eigen::Vector3d p_rh = m.FootPosition(Leg::kRH, Eigen::Vector3d(-q[0], -q[1], -q[2]));
    EXPECT_LT((p_rf - Mirror(p_lf, Leg::kRF)).norm(), 1e-12);
    EXPECT_LT((p_lh - Mirror(p_lf, Leg::kLH)).norm(), 1e-12);
    EXPECT_LT((p_rh - Mirror(p_lf, Leg::kRH)).norm(), 1e-12);
  }
  // At the reference stance the left feet are at +y and the right feet at -y.
  for (Leg leg : kAllLegs) EXPECT_GT(LeftSign(leg) * m.ReferenceFootPosition(leg).y(), 0.2) << LegName(leg);
}

TEST(RobotModel, JacobianMatchesCentralDifferences) {
  const RobotModel& m = Anymal();
  std::mt19937 rng(11);
  const double h = 1e-6;
  for (Leg leg : kAllLegs) {
    for (int i = 0; i < 1000; ++i) {
      const Eigen::Vector3d q = test::SampleLegJoints(m, leg, rng);
      const Eigen::Matrix3d J = m.FootJacobian(leg, q);
      Eigen::Matrix3d fd;
      for (int j = 0; j < 3; ++j) {
        Eigen::Vector3d dq = Eigen::Vector3d::Zero();
        dq[j] = h;
        fd.col(j) = (m.FootPosition(leg, q + dq) - m.FootPosition(leg, q - dq)) / (2.0 * h);
      }
      ASSERT_LT((J - fd).cwiseAbs().maxCoeff(), 1e-8) << LegName(leg) << " q " << q.transpose();
      Eigen::Vector3d p;
      Eigen::Matrix3d J2;
      m.FootPositionAndJacobian(leg, q, &p, &J2);
      ASSERT_EQ(p, m.FootPosition(leg, q));
      ASSERT_EQ(J2, J);
    }
  }
}

TEST(RobotModel, StaticTorquesSatisfyVirtualWork) {
  const RobotModel& m = Anymal();
  std::mt19937 rng(13);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Leg leg : kAllLegs) {
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d q = test::SampleLegJoints(m, leg, rng);
      const Eigen::Vector3d f = 100.0 * Eigen::Vector3d(n(rng), n(rng), n(rng));
      const Eigen::Vector3d dq = 1e-6 * Eigen::Vector3d(n(rng), n(rng), n(rng));
      const Eigen::Vector3d tau = m.StaticTorques(leg, q, f);
      // Equilibrium: the actuators' virtual work cancels the ground force's virtual work.
      const Eigen::Vector3d dp = (m.FootPosition(leg, q + dq) - m.FootPosition(leg, q - dq)) / 2.0;
      ASSERT_NEAR(tau.dot(dq) + f.dot(dp), 0.0, 1e-10) << LegName(leg);
      ASSERT_LT((tau + m.FootJacobian(leg, q).transpose() * f).norm(), 1e-12);
    }
  }
  // Standing: the ground pushes the foot up, the knee actuator resists folding (fore knees fold
  // towards negative KFE, hind knees towards positive KFE).
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d tau =
        m.StaticTorques(leg, LegJoints(m.ReferenceConfiguration(), leg), Eigen::Vector3d(0, 0, 75.0));
    EXPECT_GT(ForeSign(leg) * tau[2], 1.0) << LegName(leg);
  }
}

TEST(RobotModel, LegGravityTorquesAreThePotentialEnergyGradient) {
  // Holding a leg still against gravity takes tau = dV/dq, V = -m_total CoM(q) . g.
  const Eigen::Vector3d g = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0.5).normalized()) * Eigen::Vector3d(0, 0, -9.81);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  for (int trial = 0; trial < 20; ++trial) {
    JointVector q;
    for (int i = 0; i < kNumJoints; ++i) q[i] = angle(rng);
    for (Leg leg : kAllLegs) {
      const Eigen::Vector3d tau = Anymal().LegGravityTorques(leg, LegJoints(q, leg), g);
      for (int j = 0; j < kJointsPerLeg; ++j) {
        const double h = 1e-6;
        JointVector qp = q, qm = q;
        qp[kJointsPerLeg * Index(leg) + j] += h;
        qm[kJointsPerLeg * Index(leg) + j] -= h;
        const double vp = -Anymal().TotalMass() * Anymal().CenterOfMass(qp).dot(g);
        const double vm = -Anymal().TotalMass() * Anymal().CenterOfMass(qm).dot(g);
        EXPECT_NEAR(tau[j], (vp - vm) / (2 * h), 1e-6) << LegName(leg) << " joint " << j;
      }
    }
  }
}

TEST(RobotModel, LegMassMatrixGivesTheLegsKineticEnergy) {
  // 1/2 qd^T M qd against the kinetic energy of every link of the leg, its CoM's velocity and its
  // frame's angular velocity by central differences of the link poses.
  const RobotModel& m = Anymal();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    JointVector q = m.ReferenceConfiguration();
    JointVector qd = JointVector::Zero();
    for (int i = 0; i < kNumJoints; ++i) {
      q[i] += 0.3 * angle(rng);
      qd[i] = 3.0 * angle(rng);
    }
    for (Leg leg : kAllLegs) {
      const Eigen::Matrix3d M = m.LegMassMatrix(leg, LegJoints(q, leg));
      EXPECT_TRUE(M.isApprox(M.transpose(), 1e-12)) << LegName(leg);
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(M).eigenvalues().minCoeff(), 0.0) << LegName(leg);
      const double h = 1e-6;
      JointVector qp = q, qm = q;
      SetLegJoints(qp, leg, LegJoints(q, leg) + h * LegJoints(qd, leg));
      SetLegJoints(qm, leg, LegJoints(q, leg) - h * LegJoints(qd, leg));
      const std::vector<Eigen::Isometry3d> pp = m.LinkPoses(qp), pm = m.LinkPoses(qm);
      double energy = 0.0;
      for (std::size_t l = 0; l < m.Links().size(); ++l) {
        const RobotLink& link = m.Links()[l];
        if (link.leg != leg) continue;
        const Eigen::Vector3d v = (pp[l] * link.com - pm[l] * link.com) / (2 * h);
        const Eigen::AngleAxisd turn(pp[l].linear() * pm[l].linear().transpose());
        const Eigen::Vector3d w_l = turn.axis() * turn.angle() / (2 * h);
        const Eigen::Vector3d w_link = pp[l].linear().transpose() * w_l;
        energy += 0.5 * link.mass * v.squaredNorm() + 0.5 * w_link.dot(link.inertia * w_link);
      }
      const Eigen::Vector3d w = LegJoints(qd, leg);
      EXPECT_NEAR(0.5 * w.dot(M * w), energy, 1e-6 * energy + 1e-9) << LegName(leg) << " trial " << trial;
    }
  }
}

TEST(RobotModel, CenterOfMassWithKeptBodyPosesIsTheSameToTheBit) {
  // Moving one leg at a time, or all of them, reuses the unchanged legs' poses exactly.
  const RobotModel& m = Anymal();
  std::mt19937 rng(23);
  BodyPoseData data;
  JointVector q = test::SampleJoints(m, rng);
  for (int i = 0; i < 40; ++i) {
    const JointVector other = test::SampleJoints(m, rng);
    if (i % 5 == 4) {
      q = other;
    } else {
      const int leg = i % kNumLegs;
      q.segment<kJointsPerLeg>(kJointsPerLeg * leg) = other.segment<kJointsPerLeg>(kJointsPerLeg * leg);
    }
    EXPECT_EQ(m.CenterOfMass(q, &data), m.CenterOfMass(q)) << i;
  }
}

TEST(RobotModel, CenterOfMassMatchesPublishedValues) {
  const RobotModel& m = Anymal();
  // anymal_b.md section 4 / 7.1 (derived whole-body CoM in the base frame).
  EXPECT_LT((m.CenterOfMass(m.ReferenceConfiguration()) - Eigen::Vector3d(-0.0011, -0.0008, -0.0165)).norm(), 1e-3);
  EXPECT_LT((m.CenterOfMass(Uniform({-0.1, 0.7, -1.0})) - Eigen::Vector3d(-0.0011, -0.0008, -0.0216)).norm(), 1e-3);
  EXPECT_LT((m.CenterOfMass(JointVector::Zero()) - Eigen::Vector3d(-0.0011, -0.0008, -0.0343)).norm(), 1e-3);

  // Independent sum over links with LinkPoses.
  std::mt19937 rng(17);
  for (int i = 0; i < 20; ++i) {
    const JointVector q = test::SampleJoints(m, rng);
    const auto poses = m.LinkPoses(q);
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < poses.size(); ++k) weighted += m.Links()[k].mass * (poses[k] * m.Links()[k].com);
    EXPECT_LT((m.CenterOfMass(q) - weighted / m.TotalMass()).norm(), 1e-12);
  }
}

TEST(RobotModel, LinkPosesAgreeWithLegKinematics) {
  const RobotModel& m = Anymal();
  std::mt19937 rng(19);
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 100; ++i) {
    const JointVector q = test::SampleJoints(m, rng);
    m.LinkPoses(q, &poses);
    ASSERT_EQ(poses.size(), m.Links().size());
    EXPECT_TRUE(poses[0].isApprox(Eigen::Isometry3d::Identity()));
    for (Leg leg : kAllLegs) {
      const auto& foot = poses[static_cast<std::size_t>(m.LinkIndex(std::string(LegName(leg)) + "_FOOT"))];
      const auto& hip = poses[static_cast<std::size_t>(m.LinkIndex(std::string(LegName(leg)) + "_HIP"))];
      EXPECT_LT((foot * m.FootContactOffset() - m.FootPosition(leg, LegJoints(q, leg))).norm(), 1e-12);
      EXPECT_LT((hip.translation() - m.HipPosition(leg)).norm(), 1e-15);
      EXPECT_TRUE(hip.linear().isApprox(
          Eigen::AngleAxisd(LegJoints(q, leg)[0], Eigen::Vector3d::UnitX()).toRotationMatrix(), 1e-12));
    }
  }
}

TEST(RobotModel, SetLegLinkPosesMatchesTheWholeBodyPoses) {
  // Changing one leg in a LinkPoses() vector gives exactly the poses of the changed configuration.
  const RobotModel& m = Anymal();
  std::mt19937 rng(23);
  std::vector<Eigen::Isometry3d> updated;
  for (int i = 0; i < 40; ++i) {
    const JointVector q = test::SampleJoints(m, rng);
    const Leg leg = kAllLegs[static_cast<std::size_t>(i % kNumLegs)];
    const Eigen::Vector3d q_leg = test::SampleLegJoints(m, leg, rng);
    m.LinkPoses(q, &updated);
    m.SetLegLinkPoses(leg, q_leg, &updated);
    JointVector q_changed = q;
    SetLegJoints(q_changed, leg, q_leg);
    const std::vector<Eigen::Isometry3d> expected = m.LinkPoses(q_changed);
    ASSERT_EQ(updated.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_EQ(updated[k].matrix(), expected[k].matrix()) << m.Links()[k].name;
    }
  }
}

TEST(RobotModel, CollisionShapesFollowTheDescription) {
  const RobotModel& m = Anymal();
  const auto& shapes = m.CollisionShapes();
  ASSERT_EQ(shapes.size(), 40u);
  std::map<CollisionShape::Kind, int> count;
  int trunk = 0;
  for (const CollisionShape& s : shapes) {
    ++count[s.kind];
    ASSERT_GE(s.link_index, 0);
    EXPECT_EQ(m.Links()[static_cast<std::size_t>(s.link_index)].name, s.link);
    EXPECT_EQ(m.Links()[static_cast<std::size_t>(s.link_index)].leg, s.leg);
    if (!s.leg) ++trunk;
  }
  EXPECT_EQ(count[CollisionShape::Kind::kSphere], 4);
  EXPECT_EQ(count[CollisionShape::Kind::kBox], 12);
  EXPECT_EQ(count[CollisionShape::Kind::kCylinder], 24);
  EXPECT_EQ(trunk, 8);

  // Main body box and the mirrored RF thigh box (roll -0.145).
  EXPECT_EQ(shapes[0].link, "base");
  EXPECT_EQ(shapes[0].kind, CollisionShape::Kind::kBox);
  EXPECT_TRUE(shapes[0].box_size.isApprox(Eigen::Vector3d(0.531, 0.27, 0.24)));
  EXPECT_TRUE(shapes[0].pose_link.translation().isApprox(Eigen::Vector3d(0, 0, 0.08)));
  bool found_rf_thigh_box = false;
  for (const CollisionShape& s : shapes) {
    if (s.link == "RF_THIGH" && s.kind == CollisionShape::Kind::kBox) {
      found_rf_thigh_box = true;
      EXPECT_TRUE(s.pose_link.translation().isApprox(Eigen::Vector3d(0, -0.035, -0.125)));
      EXPECT_TRUE(
          s.pose_link.linear().isApprox(Eigen::AngleAxisd(-0.145, Eigen::Vector3d::UnitX()).toRotationMatrix()));
    }
  }
  EXPECT_TRUE(found_rf_thigh_box);

  // Foot sphere at the 2019 stance: centre (0.3656, 0.2632, -0.4267), lowest point -0.4577.
  const auto poses = m.LinkPoses(m.ReferenceConfiguration());
  for (const CollisionShape& s : shapes) {
    if (s.kind != CollisionShape::Kind::kSphere) continue;
    ASSERT_TRUE(s.leg.has_value());
    EXPECT_NEAR(s.radius, m.FootRadius(), 1e-12);
    const Eigen::Vector3d centre = (poses[static_cast<std::size_t>(s.link_index)] * s.pose_link).translation();
    EXPECT_LT((centre - Mirror({0.3656, 0.2632, -0.4267}, *s.leg)).norm(), 1.5e-4) << s.link;
    EXPECT_NEAR(centre.z() - s.radius, -0.4577, 1.5e-4);
  }
}

TEST(RobotModel, PlanningParametersAreLoaded) {
  const RobotModel& m = Anymal();
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d expected(0.04 * LeftSign(leg), 0.74 * ForeSign(leg), -1.08 * ForeSign(leg));
    EXPECT_TRUE(LegJoints(m.ReferenceConfiguration(), leg).isApprox(expected)) << LegName(leg);
    EXPECT_TRUE(m.WithinJointBounds(leg, expected));
    EXPECT_LT((m.ReferenceFootPosition(leg) - m.FootPosition(leg, expected)).norm(), 1e-15);
    // The nominal height puts the reference contact points on flat ground.
    EXPECT_NEAR(m.NominalBaseHeight() + m.ReferenceFootPosition(leg).z(), 0.0, 5e-4) << LegName(leg);
    EXPECT_EQ(m.LegLowerBounds(leg)[0], -1.0);
    EXPECT_EQ(m.LegUpperBounds(leg)[0], 1.0);
  }
  EXPECT_EQ(m.LegLowerBounds(Leg::kLF)[1], -0.25);
  EXPECT_EQ(m.LegLowerBounds(Leg::kRF)[1], -0.4);
  EXPECT_EQ(m.LegUpperBounds(Leg::kLH)[1], 0.4);
  EXPECT_EQ(m.LegUpperBounds(Leg::kRH)[1], 0.25);
  EXPECT_EQ(m.LegUpperBounds(Leg::kRF)[2], 0.0);
  EXPECT_EQ(m.LegLowerBounds(Leg::kLH)[2], 0.0);
  EXPECT_EQ(m.LegLowerBounds(Leg::kRF)[2], -2.35);
  EXPECT_TRUE(m.FootContactOffset().isApprox(Eigen::Vector3d(0, 0, -0.00775)));
  EXPECT_EQ(m.FootRadius(), 0.031);
  EXPECT_EQ(m.TorqueLimit(), 80.0);
  EXPECT_EQ(m.ContinuousTorqueLimit(), 40.0);
  EXPECT_EQ(m.JointVelocityLimit(), 15.0);
  EXPECT_FALSE(m.WithinJointBounds(Leg::kLF, Eigen::Vector3d(0.0, 0.7, 0.01)));
}

}  // namespace
}  // namespace rbcp
