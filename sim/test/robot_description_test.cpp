#include "robot_description.h"

#include <gtest/gtest.h>

#include <map>

#include "sim_test_util.h"

namespace rbcp::sim {
namespace {

using test::Model;

const RobotDescription& Description() {
  static const RobotDescription d = RobotDescription::FromModel(Model());
  return d;
}

TEST(RobotDescription, BodiesFollowTheJointOrder) {
  const RobotDescription& d = Description();
  ASSERT_EQ(static_cast<int>(d.bodies.size()), RobotDescription::kNumBodies);
  EXPECT_EQ(d.bodies[0].name, "base");
  for (int i = 0; i < kNumJoints; ++i) {
    const RobotBody& b = d.bodies[static_cast<std::size_t>(RobotDescription::JointBody(i))];
    EXPECT_EQ(b.joint_name, JointName(i));
    EXPECT_EQ(b.joint, RobotBody::Joint::kRevolute);
    EXPECT_EQ(b.lower_limit, -9.42);
    EXPECT_EQ(b.upper_limit, 9.42);
  }
  for (Leg leg : kAllLegs) {
    const std::string l(LegName(leg));
    const RobotBody& shank = d.bodies[static_cast<std::size_t>(RobotDescription::JointBody(3 * Index(leg) + 2))];
    EXPECT_EQ(shank.links, (std::vector<std::string>{l + "_SHANK", l + "_ADAPTER"}));
    const RobotBody& foot = d.bodies[static_cast<std::size_t>(RobotDescription::FootBody(leg))];
    EXPECT_EQ(foot.name, l + "_FOOT");
    EXPECT_TRUE(foot.is_foot);
    EXPECT_EQ(foot.joint, RobotBody::Joint::kFixed);
    EXPECT_EQ(foot.parent, RobotDescription::JointBody(3 * Index(leg) + 2));
    ASSERT_EQ(foot.shapes.size(), 1u);
    EXPECT_EQ(foot.shapes[0].primitive.kind, CollisionShape::Kind::kSphere);
    EXPECT_DOUBLE_EQ(foot.shapes[0].primitive.radius, 0.031);
  }
}

TEST(RobotDescription, MassesAndPrimitivesAreTheUrdfs) {
  const RobotDescription& d = Description();
  // The URDF's link masses: trunk plus four legs of hip, thigh, shank, adapter and foot.
  EXPECT_NEAR(d.total_mass, 16.793507758 + 4 * (1.42462064 + 1.634976467 + 0.207204302 + 0.140170767 + 0.001), 1e-9);
  EXPECT_NEAR(d.total_mass, Model().TotalMass(), 1e-12);
  std::map<std::string, int> model_count, sim_count;
  for (const CollisionShape& s : Model().CollisionShapes()) ++model_count[s.link];
  for (const RobotBody& b : d.bodies) {
    for (const BodyShape& s : b.shapes) ++sim_count[s.primitive.link];
  }
  EXPECT_EQ(sim_count, model_count);
}

/// Whole-robot inertia about the CoM in the base frame at q, from per-link data of the model.
Eigen::Matrix3d ModelInertia(const JointVector& q, Eigen::Vector3d* com) {
  const std::vector<Eigen::Isometry3d> poses = Model().LinkPoses(q);
  double m = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    m += Model().Links()[i].mass;
    c += Model().Links()[i].mass * (poses[i] * Model().Links()[i].com);
  }
  c /= m;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const RobotLink& link = Model().Links()[i];
    const Eigen::Matrix3d R = poses[i].linear();
    const Eigen::Vector3d r = poses[i] * link.com - c;
    I += R * link.inertia * R.transpose() + link.mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  *com = c;
  return I;
}

/// The same from the simulator's bodies: merged, diagonalised inertias placed by the joint chain.
Eigen::Matrix3d DescriptionInertia(const JointVector& q, Eigen::Vector3d* com) {
  const RobotDescription& d = Description();
  std::vector<Eigen::Isometry3d> body_pose(d.bodies.size());
  for (std::size_t b = 0; b < d.bodies.size(); ++b) {
    const RobotBody& body = d.bodies[b];
    if (body.parent < 0) {
      body_pose[b] = Eigen::Isometry3d::Identity();
      continue;
    }
    Eigen::Isometry3d joint = Eigen::Isometry3d::Identity();
    if (body.joint == RobotBody::Joint::kRevolute) joint.linear() = Eigen::AngleAxisd(q[static_cast<int>(b) - 1], body.axis).toRotationMatrix();
    body_pose[b] = body_pose[static_cast<std::size_t>(body.parent)] * body.parent_to_body * joint;
  }
  double m = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t b = 0; b < d.bodies.size(); ++b) {
    m += d.bodies[b].mass;
    c += d.bodies[b].mass * (body_pose[b] * d.bodies[b].inertial_frame.translation());
  }
  c /= m;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (std::size_t b = 0; b < d.bodies.size(); ++b) {
    const RobotBody& body = d.bodies[b];
    const Eigen::Isometry3d frame = body_pose[b] * body.inertial_frame;
    const Eigen::Vector3d r = frame.translation() - c;
    I += frame.linear() * body.principal_inertia.asDiagonal() * frame.linear().transpose() +
         body.mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  *com = c;
  return I;
}

TEST(RobotDescription, MergedPrincipalInertiasGiveTheUrdfsWholeBodyInertia) {
  JointVector q_bent;
  q_bent << 0.3, 1.1, -1.9, -0.2, 0.4, -0.6, 0.5, -1.2, 2.0, -0.4, -0.3, 0.7;
  for (const JointVector& q : {Model().ReferenceConfiguration(), JointVector::Zero().eval(), q_bent}) {
    Eigen::Vector3d c_model, c_sim;
    const Eigen::Matrix3d I_model = ModelInertia(q, &c_model);
    const Eigen::Matrix3d I_sim = DescriptionInertia(q, &c_sim);
    EXPECT_NEAR((c_model - c_sim).norm(), 0.0, 1e-12);
    EXPECT_NEAR((I_model - I_sim).norm(), 0.0, 1e-12);
    EXPECT_NEAR(c_model.z(), Model().CenterOfMass(q).z(), 1e-12);
  }
}

TEST(RobotDescription, BodyInertiasArePrincipal) {
  for (const RobotBody& b : Description().bodies) {
    const Eigen::Matrix3d R = b.inertial_frame.linear();
    EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12) << b.name;
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12) << b.name;
    EXPECT_NEAR((R * b.principal_inertia.asDiagonal() * R.transpose() - b.inertia_body).norm(), 0.0, 1e-15) << b.name;
  }
  // The trunk's products of inertia are not negligible next to Iyy - Izz: its principal axes
  // turn by about 5 degrees about x.
  const Eigen::AngleAxisd turn(Description().bodies[0].inertial_frame.linear());
  EXPECT_GT(turn.angle(), 0.05);
}

TEST(RobotDescription, PrincipalAxesOfADiagonalTensorAreTheCoordinateAxes) {
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
  PrincipalAxes(Eigen::Vector3d(3.0, 1.0, 2.0).asDiagonal(), &R, &p);
  EXPECT_TRUE(R.isIdentity(1e-15));
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(3.0, 1.0, 2.0)));
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d I = Q * Eigen::Vector3d(0.5, 0.2, 0.9).asDiagonal() * Q.transpose();
  PrincipalAxes(I, &R, &p);
  EXPECT_NEAR((R * p.asDiagonal() * R.transpose() - I).norm(), 0.0, 1e-14);
  EXPECT_NEAR((R - Q).norm(), 0.0, 1e-12);
}

TEST(RobotDescription, EveryLinkOfTheModelIsInOneBody) {
  std::map<std::string, int> count;
  for (const RobotBody& b : Description().bodies) {
    ASSERT_FALSE(b.links.empty());
    EXPECT_EQ(b.links.front(), b.name);
    for (const std::string& link : b.links) ++count[link];
  }
  EXPECT_EQ(count.size(), Model().Links().size());
  for (const RobotLink& link : Model().Links()) EXPECT_EQ(count[link.name], 1) << link.name;
}

}  // namespace
}  // namespace rbcp::sim
