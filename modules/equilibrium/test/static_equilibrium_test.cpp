#include "rbcp/equilibrium/static_equilibrium.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>
#include <cmath>

#include "rbcp/core/error.h"
#include "rbcp/equilibrium/support_polygon.h"

namespace rbcp {
namespace {

constexpr double kMass = 30.42;            // [kg] ANYmal B
constexpr double kWeight = kMass * kGravity;  // [N]
constexpr double kA = 0.37, kB = 0.26;     // [m] half length and half width of the stance

double SinAtan(double mu) { return mu / std::sqrt(1.0 + mu * mu); }

EquilibriumConfig WithFriction(double mu) {
  EquilibriumConfig c;
  c.friction = mu;
  return c;
}

// Feet LF, RF, LH, RH on flat ground z = 0.
std::vector<ContactPoint> FlatStance() {
  return {{{kA, kB, 0}, {0, 0, 1}}, {{kA, -kB, 0}, {0, 0, 1}}, {{-kA, kB, 0}, {0, 0, 1}}, {{-kA, -kB, 0}, {0, 0, 1}}};
}

// Robustness on flat ground of the rectangle stance: sin(atan mu) times the largest achievable
// smallest normal force, W / 4 (1 - max(|x| / a, |y| / b)) (normal forces are W / 4 (1 +- x / a
// +- y / b) plus a multiple of the internal mode (+1, -1, -1, +1)).
double FlatRectangleRobustness(double mu, double x, double y) {
  return SinAtan(mu) * kWeight / 4.0 * (1.0 - std::max(std::abs(x) / kA, std::abs(y) / kB));
}

// Smallest achievable largest normal force on the flat rectangle stance: the normal forces are
// W / 4 (1 +- x / a +- y / b) + s (+1, -1, -1, +1) with s such that none is negative. The
// largest of these four lines is convex in s; its minimum lies at an end of the allowed interval
// or where a rising line crosses a falling one.
double FlatRectanglePeakNormalForce(double x, double y) {
  const double u = x / kA, v = y / kB;
  const std::array<double, 4> base = {1 + u + v, 1 + u - v, 1 - u + v, 1 - u - v};  // LF, RF, LH, RH
  const std::array<double, 4> sign = {+1, -1, -1, +1};
  const double s_lo = -std::min(base[0], base[3]), s_hi = std::min(base[1], base[2]);
  std::vector<double> candidates = {s_lo, s_hi};
  for (int rise : {0, 3}) {
    for (int fall : {1, 2}) candidates.push_back((base[fall] - base[rise]) / 2.0);
  }
  double best = std::numeric_limits<double>::infinity();
  for (double s : candidates) {
    if (s < s_lo || s > s_hi) continue;
    double peak = 0.0;
    for (int i = 0; i < 4; ++i) peak = std::max(peak, base[i] + sign[i] * s);
    best = std::min(best, peak);
  }
  return kWeight / 4.0 * best;
}

// Four feet on a plane through the origin inclined by tilt_rad, rising towards heading_rad.
std::vector<ContactPoint> SlopeStance(double tilt_rad, double heading_rad) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(heading_rad, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-tilt_rad, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  std::vector<ContactPoint> out;
  for (const auto& c : FlatStance()) out.push_back({R * c.position, R * c.normal});
  return out;
}

// True when f is inside the cone spanned by the (counter-clockwise) generators g.
bool InsidePyramid(const Eigen::Matrix3Xd& g, const Eigen::Vector3d& f, double tol) {
  for (int j = 0; j < g.cols(); ++j) {
    const Eigen::Vector3d face = g.col(j).cross(g.col((j + 1) % g.cols()));
    if (face.normalized().dot(f) < -tol) return false;
  }
  return true;
}

void ExpectBalanced(const std::vector<ContactPoint>& contacts, const Eigen::Vector3d& com,
                    const std::vector<Eigen::Vector3d>& forces) {
  ASSERT_EQ(forces.size(), contacts.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < forces.size(); ++i) {
    sum += forces[i];
    moment += (contacts[i].position - com).cross(forces[i]);
  }
  EXPECT_NEAR((sum - Eigen::Vector3d(0, 0, kWeight)).norm(), 0.0, 1e-5 * kWeight);
  EXPECT_NEAR(moment.norm(), 0.0, 1e-5 * kWeight);
}

TEST(StaticEquilibrium, FlatStanceCentredIsStableWithTheHandComputedRobustness) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(FlatStance());
  const EquilibriumResult r = eq.Robustness(Eigen::Vector3d(0, 0, 0.45));
  EXPECT_TRUE(r.feasible);
  EXPECT_EQ(r.status, EquilibriumStatus::kBalanced);
  EXPECT_TRUE(r.reason.empty());
  // Every foot carries W / 4 straight down its normal: 298.4 N / 4 * sin(atan 0.5) = 33.4 N.
  EXPECT_NEAR(r.robustness_N, kWeight / 4.0 * SinAtan(0.5), 1e-6);
  EXPECT_TRUE(eq.MeetsThreshold(r));
}

TEST(StaticEquilibrium, FlatStanceRobustnessMatchesTheClosedFormEverywhere) {
  for (double mu : {0.3, 0.5, 1.0}) {
    StaticEquilibrium eq(kMass, WithFriction(mu));
    eq.SetContacts(FlatStance());
    for (double x : {-0.5, -0.3, -0.1, 0.0, 0.05, 0.2, 0.36, 0.45}) {
      for (double y : {-0.3, -0.1, 0.0, 0.15, 0.25}) {
        for (double z : {0.3, 0.6}) {
          const EquilibriumResult r = eq.Robustness(Eigen::Vector3d(x, y, z));
          const double expected = FlatRectangleRobustness(mu, x, y);
          EXPECT_NEAR(r.robustness_N, expected, 1e-6 * kWeight) << "mu " << mu << " com " << x << ", " << y;
          EXPECT_EQ(r.feasible, expected >= 0.0);
          EXPECT_EQ(r.status, expected >= 0.0 ? EquilibriumStatus::kBalanced : EquilibriumStatus::kOutsideCones);
        }
      }
    }
  }
}

TEST(StaticEquilibrium, RobustnessFallsAsTheCoMApproachesAnEdgeAndIsNegativeBeyond) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(FlatStance());
  double previous = eq.Robustness(Eigen::Vector3d(0, 0, 0.45)).robustness_N;
  for (double x = 0.05; x < 0.6; x += 0.05) {
    const EquilibriumResult r = eq.Robustness(Eigen::Vector3d(x, 0.0, 0.45));
    EXPECT_LT(r.robustness_N, previous) << "x " << x;
    previous = r.robustness_N;
    EXPECT_EQ(r.feasible, x < kA);
  }
  const EquilibriumResult outside = eq.Robustness(Eigen::Vector3d(0.5, 0.0, 0.45));
  EXPECT_FALSE(outside.feasible);
  EXPECT_EQ(outside.status, EquilibriumStatus::kOutsideCones);
  EXPECT_LT(outside.robustness_N, 0.0);
  EXPECT_FALSE(outside.reason.empty());
  EXPECT_FALSE(eq.MeetsThreshold(outside));
  // Close to the edge: balanced, but below the 2 N threshold.
  const EquilibriumResult near_edge = eq.Robustness(Eigen::Vector3d(kA - 0.005, 0.0, 0.45));
  EXPECT_TRUE(near_edge.feasible);
  EXPECT_GT(near_edge.robustness_N, 0.0);
  EXPECT_FALSE(eq.MeetsThreshold(near_edge));
}

TEST(StaticEquilibrium, ThreeFootStanceStableInsideTheTriangleOnly) {
  // LH swings. The normal forces are W times the barycentric coordinates of the CoM in the
  // triangle LF, RF, RH; the robustness is sin(atan mu) times the smallest.
  auto stance = FlatStance();
  stance.erase(stance.begin() + 2);
  const Eigen::Vector2d lf(kA, kB), rf(kA, -kB), rh(-kA, -kB);
  auto barycentric_min = [&](const Eigen::Vector2d& p) {
    Eigen::Matrix3d M;
    M << lf.x(), rf.x(), rh.x(), lf.y(), rf.y(), rh.y(), 1, 1, 1;
    return M.colPivHouseholderQr().solve(Eigen::Vector3d(p.x(), p.y(), 1)).minCoeff();
  };
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(stance);
  const Eigen::Vector2d centroid = (lf + rf + rh) / 3.0;
  for (const Eigen::Vector2d& p : {centroid, Eigen::Vector2d(0.2, -0.1), Eigen::Vector2d(0.0, -0.05),
                                   Eigen::Vector2d(-0.2, 0.15), Eigen::Vector2d(0.0, 0.1)}) {
    const Eigen::Vector3d com(p.x(), p.y(), 0.45);
    const EquilibriumResult r = eq.Robustness(com);
    const double expected = SinAtan(0.5) * kWeight * barycentric_min(p);
    EXPECT_NEAR(r.robustness_N, expected, 1e-6 * kWeight) << p.transpose();
    EXPECT_EQ(r.feasible, SupportPolygonMargin(stance, com) > 0.0) << p.transpose();
  }
  EXPECT_NEAR(eq.Robustness(Eigen::Vector3d(centroid.x(), centroid.y(), 0.45)).robustness_N,
              SinAtan(0.5) * kWeight / 3.0, 1e-6);
  EXPECT_FALSE(eq.Robustness(Eigen::Vector3d(-0.2, 0.15, 0.45)).feasible);
}

TEST(StaticEquilibrium, SlopeOfThirtyDegreesNeedsMoreFrictionThanPointFive) {
  // tan 30 deg = 0.577: no distribution of forces on one plane holds the robot with mu = 0.5,
  // whatever the cone linearisation; with mu = 0.7 vertical foot forces are inside the cones.
  // The CoM is straight above the centre of the feet.
  const Eigen::Vector3d com(0.0, 0.0, 0.5);
  for (double heading : {0.0, M_PI / 4, 2.0, -2.8}) {
    const auto stance = SlopeStance(30.0 * M_PI / 180.0, heading);
    StaticEquilibrium low(kMass, WithFriction(0.5));
    const EquilibriumResult r_low = low.Robustness(stance, com);
    EXPECT_FALSE(r_low.feasible) << "heading " << heading;
    EXPECT_EQ(r_low.status, EquilibriumStatus::kOutsideCones);
    EXPECT_LT(r_low.robustness_N, 0.0);

    StaticEquilibrium high(kMass, WithFriction(0.7));
    const EquilibriumResult r_high = high.Robustness(stance, com);
    EXPECT_TRUE(r_high.feasible) << "heading " << heading;
    EXPECT_GT(r_high.robustness_N, 0.0);
  }
}

TEST(StaticEquilibrium, RobustnessGrowsWithFriction) {
  const auto slope = SlopeStance(30.0 * M_PI / 180.0, 0.4);
  const Eigen::Vector3d com(0.02, -0.01, 0.5);
  double previous_slope = -std::numeric_limits<double>::infinity();
  double previous_flat = 0.0;
  bool was_feasible = false;
  for (double mu = 0.4; mu <= 1.5; mu += 0.05) {
    StaticEquilibrium eq(kMass, WithFriction(mu));
    const EquilibriumResult r = eq.Robustness(slope, com);
    if (was_feasible) {
      EXPECT_TRUE(r.feasible) << "mu " << mu;
      EXPECT_GE(r.robustness_N, previous_slope - 1e-6) << "mu " << mu;
    }
    was_feasible = r.feasible;
    previous_slope = r.robustness_N;
    const double flat = eq.Robustness(FlatStance(), Eigen::Vector3d(0.1, 0.05, 0.45)).robustness_N;
    EXPECT_GT(flat, previous_flat);
    previous_flat = flat;
  }
  EXPECT_TRUE(was_feasible);
}

TEST(StaticEquilibrium, ContactsThatCannotHoldTheCoMGiveNoBalance) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  const std::vector<ContactPoint> two = {{{0.3, 0.2, 0}, {0, 0, 1}}, {{-0.3, -0.2, 0}, {0, 0, 1}}};
  const EquilibriumResult r = eq.Robustness(two, Eigen::Vector3d(0.1, -0.1, 0.45));
  EXPECT_FALSE(r.feasible);
  EXPECT_EQ(r.status, EquilibriumStatus::kNoBalance);
  EXPECT_EQ(r.robustness_N, -std::numeric_limits<double>::infinity());
  EXPECT_FALSE(r.reason.empty());

  const ContactForces f = eq.DistributeForces(Eigen::Vector3d(0.1, -0.1, 0.45));
  EXPECT_FALSE(f.feasible);
  EXPECT_EQ(f.status, EquilibriumStatus::kNoBalance);

  const EquilibriumResult none = eq.Robustness({}, Eigen::Vector3d(0, 0, 0.45));
  EXPECT_FALSE(none.feasible);
  EXPECT_EQ(none.status, EquilibriumStatus::kNoBalance);
  EXPECT_FALSE(eq.DistributeForces(Eigen::Vector3d(0, 0, 0.45)).feasible);
}

TEST(StaticEquilibrium, OpposingWallsGiveAnUnboundedMargin) {
  // Feet pressed against two facing walls can squeeze as hard as they like.
  const std::vector<ContactPoint> chimney = {{{-0.5, 0.3, 0}, {1, 0, 0}},
                                             {{-0.5, -0.3, 0}, {1, 0, 0}},
                                             {{0.5, 0.3, 0}, {-1, 0, 0}},
                                             {{0.5, -0.3, 0}, {-1, 0, 0}}};
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  const EquilibriumResult r = eq.Robustness(chimney, Eigen::Vector3d(0, 0, 0.1));
  EXPECT_TRUE(r.feasible);
  EXPECT_EQ(r.status, EquilibriumStatus::kUnboundedMargin);
  EXPECT_EQ(r.robustness_N, std::numeric_limits<double>::infinity());
  EXPECT_TRUE(eq.MeetsThreshold(r));
}

TEST(StaticEquilibrium, ForcesOfTheCentredFlatStanceAreAQuarterOfTheWeightEach) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(FlatStance());
  const ContactForces f = eq.DistributeForces(Eigen::Vector3d(0, 0, 0.45));
  ASSERT_TRUE(f.feasible);
  EXPECT_EQ(f.status, EquilibriumStatus::kBalanced);
  for (const auto& force : f.forces_N) EXPECT_NEAR((force - Eigen::Vector3d(0, 0, kWeight / 4)).norm(), 0.0, 1e-5);
  EXPECT_NEAR(f.max_normal_force_N, kWeight / 4, 1e-5);
  EXPECT_NEAR(f.friction_margin_N, kWeight / 4 * SinAtan(0.5), 1e-5);
}

TEST(StaticEquilibrium, ForcesBalanceGravityInsideTheConesWithTheSmallestPeakNormalForce) {
  const EquilibriumConfig config;
  StaticEquilibrium eq(kMass, config);
  eq.SetContacts(FlatStance());
  // For the second CoM (towards LH) RF's normal force reaches zero before the peak is balanced.
  for (const Eigen::Vector3d& com : {Eigen::Vector3d(0.1, -0.05, 0.45), Eigen::Vector3d(-0.2, 0.1, 0.5)}) {
    const ContactForces f = eq.DistributeForces(com);
    ASSERT_TRUE(f.feasible);
    ExpectBalanced(eq.Contacts(), com, f.forces_N);
    const double t_min = FlatRectanglePeakNormalForce(com.x(), com.y());
    EXPECT_GE(f.max_normal_force_N, t_min - 1e-5);
    EXPECT_LE(f.max_normal_force_N, t_min * (1 + config.normal_force_slack) + 1e-5);
    for (std::size_t i = 0; i < f.forces_N.size(); ++i) {
      EXPECT_LE(f.forces_N[i].dot(eq.Contacts()[i].normal), f.max_normal_force_N + 1e-9);
      EXPECT_TRUE(InsidePyramid(eq.Generators().middleCols(4 * static_cast<int>(i), 4), f.forces_N[i], 1e-6));
    }
    const EquilibriumResult r = eq.Robustness(com);
    EXPECT_GT(f.friction_margin_N, 0.0);
    EXPECT_LE(f.friction_margin_N, r.robustness_N + 1e-6);
  }

  // On the slope the forces need friction but stay inside the cones.
  const auto slope = SlopeStance(25.0 * M_PI / 180.0, 1.0);
  const Eigen::Vector3d com(0.0, 0.0, 0.5);
  eq.SetContacts(slope);
  const ContactForces f = eq.DistributeForces(com);
  ASSERT_TRUE(f.feasible);
  ExpectBalanced(slope, com, f.forces_N);
  for (std::size_t i = 0; i < f.forces_N.size(); ++i) {
    const Eigen::Vector3d& n = eq.Contacts()[i].normal;
    const double fn = f.forces_N[i].dot(n);
    EXPECT_GT(fn, 0.0);
    EXPECT_LE((f.forces_N[i] - fn * n).norm(), config.friction * fn + 1e-6);
    EXPECT_TRUE(InsidePyramid(eq.Generators().middleCols(4 * static_cast<int>(i), 4), f.forces_N[i], 1e-6));
  }
}

TEST(StaticEquilibrium, NoForcesWhenTheCoMIsOutsideTheSupport) {
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  eq.SetContacts(FlatStance());
  const ContactForces f = eq.DistributeForces(Eigen::Vector3d(0.5, 0.0, 0.45));
  EXPECT_FALSE(f.feasible);
  EXPECT_EQ(f.status, EquilibriumStatus::kOutsideCones);
  EXPECT_FALSE(f.reason.empty());
  EXPECT_TRUE(f.forces_N.empty());
  // The model recovers for the next query.
  EXPECT_TRUE(eq.DistributeForces(Eigen::Vector3d(0.0, 0.0, 0.45)).feasible);
}

TEST(StaticEquilibrium, ResultsDependOnlyOnTheQuery) {
  const auto slope = SlopeStance(20.0 * M_PI / 180.0, 0.3);
  const Eigen::Vector3d com(0.05, 0.02, 0.5);
  StaticEquilibrium a(kMass, EquilibriumConfig{});
  a.SetContacts(slope);
  const EquilibriumResult r1 = a.Robustness(com);
  const ContactForces f1 = a.DistributeForces(com);
  // Unrelated queries in between, on the same instance.
  a.Robustness(Eigen::Vector3d(0.3, -0.2, 0.4));
  a.DistributeForces(Eigen::Vector3d(-0.1, 0.1, 0.4));
  a.Robustness(FlatStance(), Eigen::Vector3d(0.6, 0, 0.4));
  a.SetContacts(slope);
  const EquilibriumResult r2 = a.Robustness(com);
  const ContactForces f2 = a.DistributeForces(com);
  StaticEquilibrium b(kMass, EquilibriumConfig{});
  const EquilibriumResult r3 = b.Robustness(slope, com);
  const ContactForces f3 = b.DistributeForces(com);
  EXPECT_EQ(r1.robustness_N, r2.robustness_N);
  EXPECT_EQ(r1.robustness_N, r3.robustness_N);
  ASSERT_EQ(f1.forces_N.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(f1.forces_N[i], f2.forces_N[i]);
    EXPECT_EQ(f1.forces_N[i], f3.forces_N[i]);
  }
}

TEST(StaticEquilibrium, RobustnessScalesWithMass) {
  StaticEquilibrium light(10.0, EquilibriumConfig{});
  StaticEquilibrium heavy(40.0, EquilibriumConfig{});
  const Eigen::Vector3d com(0.1, 0.05, 0.45);
  EXPECT_NEAR(heavy.Robustness(FlatStance(), com).robustness_N, 4.0 * light.Robustness(FlatStance(), com).robustness_N,
              1e-6);
}

TEST(StaticEquilibrium, RejectsBadInput) {
  EXPECT_THROW(StaticEquilibrium(0.0, EquilibriumConfig{}), InputError);
  EquilibriumConfig bad;
  bad.generators_per_contact = 2;
  EXPECT_THROW(StaticEquilibrium(kMass, bad), InputError);
  StaticEquilibrium eq(kMass, EquilibriumConfig{});
  EXPECT_THROW(eq.SetContacts({{{0, 0, 0}, {0, 0, 0}}}), InputError);
  EXPECT_THROW(eq.SetContacts({{{NAN, 0, 0}, {0, 0, 1}}}), InputError);
  eq.SetContacts(FlatStance());
  EXPECT_THROW(eq.Robustness(Eigen::Vector3d(0, INFINITY, 0)), InputError);
  // Normals are normalised on input.
  auto scaled = FlatStance();
  for (auto& c : scaled) c.normal *= 5.0;
  EXPECT_NEAR(eq.Robustness(scaled, Eigen::Vector3d(0, 0, 0.45)).robustness_N, kWeight / 4.0 * SinAtan(0.5), 1e-6);
}

}  // namespace
}  // namespace rbcp
