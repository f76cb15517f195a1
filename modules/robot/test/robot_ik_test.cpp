#include <gtest/gtest.h>

#include <random>

#include "rbcp/robot/robot_model.h"
#include "robot_test_util.h"

namespace rbcp {
namespace {

using test::Anymal;

TEST(RobotIk, InvertsForwardKinematicsOverThePlanningBounds) {
  const RobotModel& m = Anymal();
  std::mt19937 rng(20190531);
  for (Leg leg : kAllLegs) {
    int below_hip = 0;      // sampled foot below the hip: the solver must return the sampled q
    int above_kept = 0;     // foot above the hip, the below-hip alternative is out of bounds
    int above_swapped = 0;  // foot above the hip, the in-bounds below-hip alternative is returned
    for (int i = 0; i < 10000; ++i) {
      const Eigen::Vector3d q = test::SampleLegJoints(m, leg, rng);
      const Eigen::Vector3d p = m.FootPosition(leg, q);
      const IkResult ik = m.SolveLegIk(leg, p);
      ASSERT_TRUE(ik.ok()) << LegName(leg) << " q " << q.transpose() << ": " << ik.reason;
      ASSERT_TRUE(ik.reason.empty());
      ASSERT_LT((m.FootPosition(leg, ik.q) - p).norm(), 1e-9) << LegName(leg) << " q " << q.transpose();
      ASSERT_TRUE(m.WithinJointBounds(leg, ik.q));
      // X configuration.
      ASSERT_LE(ForeSign(leg) * ik.q[2], 1e-9);
      if (test::InHipFrame(m, leg, q[0], p).z() <= 0.0) {
        ++below_hip;
        ASSERT_LT((ik.q - q).cwiseAbs().maxCoeff(), 1e-9) << LegName(leg) << " q " << q.transpose();
      } else if ((ik.q - q).cwiseAbs().maxCoeff() < 1e-9) {
        ++above_kept;
      } else {
        ++above_swapped;
        ASSERT_LT(test::InHipFrame(m, leg, ik.q[0], p).z(), 0.0) << LegName(leg) << " q " << q.transpose();
      }
    }
    EXPECT_GT(below_hip, 7000) << LegName(leg);
    // Both above-hip cases occur in the sample (about 4 % each with this seed).
    EXPECT_GT(above_kept, 100) << LegName(leg);
    EXPECT_GT(above_swapped, 100) << LegName(leg);
  }
}

TEST(RobotIk, ReturnsTheReferenceConfiguration) {
  const RobotModel& m = Anymal();
  for (Leg leg : kAllLegs) {
    const IkResult ik = m.SolveLegIk(leg, m.ReferenceFootPosition(leg));
    ASSERT_TRUE(ik.ok()) << ik.reason;
    EXPECT_LT((ik.q - LegJoints(m.ReferenceConfiguration(), leg)).norm(), 1e-12) << LegName(leg);
  }
}

TEST(RobotIk, ReportsUnreachableTargets) {
  const RobotModel& m = Anymal();
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d hip = m.HipPosition(leg);
    // 2 m away.
    IkResult ik = m.SolveLegIk(leg, hip + Eigen::Vector3d(2.0 * ForeSign(leg), 0.0, -0.3));
    EXPECT_EQ(ik.status, IkResult::Status::kOutOfReach) << LegName(leg);
    EXPECT_NE(ik.reason.find("beyond the stretched leg"), std::string::npos) << ik.reason;
    EXPECT_NE(ik.reason.find(std::string(LegName(leg))), std::string::npos) << ik.reason;
    // At the hip: inside the HAA offset cylinder.
    ik = m.SolveLegIk(leg, hip);
    EXPECT_EQ(ik.status, IkResult::Status::kOutOfReach);
    EXPECT_NE(ik.reason.find("HAA axis"), std::string::npos) << ik.reason;
    ik = m.SolveLegIk(leg, hip + Eigen::Vector3d(0.3, 0.05 * LeftSign(leg), -0.1));
    EXPECT_EQ(ik.status, IkResult::Status::kOutOfReach);
    EXPECT_NE(ik.reason.find("HAA axis"), std::string::npos) << ik.reason;
    // On the HFE axis, outside the HAA cylinder: nearer than the folded knee allows.
    ik = m.SolveLegIk(leg, hip + Eigen::Vector3d(0.0635 * ForeSign(leg), 0.13 * LeftSign(leg), -0.01));
    EXPECT_EQ(ik.status, IkResult::Status::kOutOfReach);
    EXPECT_NE(ik.reason.find("folded leg"), std::string::npos) << ik.reason;
    // Not a number.
    ik = m.SolveLegIk(leg, Eigen::Vector3d(0.3, std::nan(""), -0.4));
    EXPECT_EQ(ik.status, IkResult::Status::kOutOfReach);
  }
}

TEST(RobotIk, ReportsTargetsOutsideTheJointBoundsWithoutClamping) {
  const RobotModel& m = Anymal();
  for (Leg leg : kAllLegs) {
    const double fs = ForeSign(leg);
    const double ls = LeftSign(leg);
    // Nearly stretched knee bent the wrong way (fore KFE > 0, hind KFE < 0), still on the X side
    // of the stretched leg, so the analytic solution is exactly this configuration.
    const Eigen::Vector3d q_knee(0.0, 0.5 * fs, 0.1 * fs);
    IkResult ik = m.SolveLegIk(leg, m.FootPosition(leg, q_knee));
    EXPECT_EQ(ik.status, IkResult::Status::kOutsideJointBounds) << LegName(leg);
    EXPECT_NE(ik.reason.find(std::string(LegName(leg)) + "_KFE"), std::string::npos) << ik.reason;
    EXPECT_LT((ik.q - q_knee).norm(), 1e-9) << ik.q.transpose();

    // Abduction beyond the HAA bound.
    const Eigen::Vector3d q_haa(1.3 * ls, 0.7 * fs, -1.0 * fs);
    ik = m.SolveLegIk(leg, m.FootPosition(leg, q_haa));
    EXPECT_EQ(ik.status, IkResult::Status::kOutsideJointBounds) << LegName(leg);
    EXPECT_NE(ik.reason.find(std::string(LegName(leg)) + "_HAA"), std::string::npos) << ik.reason;
    EXPECT_NE(ik.reason.find("1.3000"), std::string::npos) << ik.reason;
    EXPECT_LT((m.FootPosition(leg, ik.q) - m.FootPosition(leg, q_haa)).norm(), 1e-9);

    // HFE beyond its bound (thigh swung too far forward for a fore leg, backward for a hind leg).
    const Eigen::Vector3d q_hfe(0.0, -0.6 * fs, -0.5 * fs);
    ik = m.SolveLegIk(leg, m.FootPosition(leg, q_hfe));
    EXPECT_EQ(ik.status, IkResult::Status::kOutsideJointBounds) << LegName(leg);
    EXPECT_NE(ik.reason.find(std::string(LegName(leg)) + "_HFE"), std::string::npos) << ik.reason;
  }
}

}  // namespace
}  // namespace rbcp
