#include "rbcp/limb_database/limb_database.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "leg_self_collision.h"
#include "limb_database_test_util.h"
#include "rbcp/core/error.h"

namespace rbcp {
namespace {

using test::Anymal;
using test::SmallConfig;

constexpr int kSamples = 5000;

const LimbDatabase& Database() {
  static const LimbDatabase db = LimbDatabase::Build(Anymal(), SmallConfig(kSamples));
  return db;
}

Eigen::Isometry3d BasePose() {
  return Eigen::Translation3d(1.0, -2.0, Anymal().NominalBaseHeight()) *
         Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX());
}

/// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Checks a query against every sample of the leg: candidates are exactly the samples whose foot
/// (at the base pose) is within max_distance of the surface, up to a 1e-9 m band for rounding.
/// `distance_W` is an independent distance to the surface.
template <typename Distance>
void ExpectCompleteAndSound(Leg leg, const Eigen::Isometry3d& base, double max_distance,
                            const std::vector<FootholdCandidate>& candidates, Distance distance_W) {
  const LimbDatabase& db = Database();
  std::set<int> found;
  for (const FootholdCandidate& c : candidates) {
    EXPECT_TRUE(found.insert(c.sample).second) << "duplicate sample " << c.sample;
    const LimbSample s = db.Sample(leg, c.sample);
    EXPECT_EQ(c.leg, leg);
    EXPECT_LE((c.foot_W - base * s.foot_B).norm(), 1e-12);
    EXPECT_EQ(c.static_score, s.score);
    const double d = distance_W(c.foot_W);
    EXPECT_LE(d, max_distance + 1e-9);
    EXPECT_NEAR(c.distance, d, 1e-9);
    EXPECT_NEAR((c.closest_W - c.foot_W).norm(), c.distance, 1e-9);
    EXPECT_NEAR(distance_W(c.closest_W), 0.0, 1e-9);
  }
  for (int i = 0; i < db.NumSamples(leg); ++i) {
    if (distance_W(base * db.Sample(leg, i).foot_B) <= max_distance - 1e-9) {
      EXPECT_TRUE(found.count(i)) << "sample " << i << " missing from the candidates";
    }
  }
}

TEST(LimbDatabase, SamplesLieWithinBoundsWithTheirForwardKinematics) {
  const LimbDatabase& db = Database();
  for (Leg leg : kAllLegs) {
    ASSERT_EQ(db.NumSamples(leg), kSamples);
    for (int i = 0; i < kSamples; ++i) {
      const LimbSample s = db.Sample(leg, i);
      EXPECT_TRUE(Anymal().WithinJointBounds(leg, s.q)) << LegName(leg) << " sample " << i;
      EXPECT_LE((s.foot_B - Anymal().FootPosition(leg, s.q)).norm(), 1e-12);
    }
    // Some draws were in self-collision, and none survived.
    EXPECT_GT(db.Draws(leg), kSamples - 1);
    EXPECT_LT(db.Draws(leg), 2 * kSamples);
  }
  EXPECT_THROW(db.Sample(Leg::kLF, kSamples), InputError);
  EXPECT_THROW(db.Sample(Leg::kLF, -1), InputError);
}

TEST(LimbDatabase, SamplesAreFreeOfSelfCollision) {
  const LimbDatabase& db = Database();
  for (Leg leg : kAllLegs) {
    const limb_database_detail::LegSelfCollision filter(Anymal(), leg);
    for (int i = 0; i < db.NumSamples(leg); ++i) {
      EXPECT_FALSE(filter.InCollision(db.Sample(leg, i).q)) << LegName(leg) << " sample " << i;
    }
  }
}

TEST(LimbDatabase, SamplesCoverTheJointRanges) {
  // Uniform draws: each joint's samples spread over (nearly) its whole planning range.
  const LimbDatabase& db = Database();
  for (Leg leg : kAllLegs) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo, mean = Eigen::Vector3d::Zero();
    for (int i = 0; i < db.NumSamples(leg); ++i) {
      const Eigen::Vector3d q = db.Sample(leg, i).q;
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
      mean += q / db.NumSamples(leg);
    }
    const Eigen::Vector3d range = Anymal().LegUpperBounds(leg) - Anymal().LegLowerBounds(leg);
    for (int j = 0; j < 3; ++j) {
      EXPECT_LT(lo[j] - Anymal().LegLowerBounds(leg)[j], 0.02 * range[j]) << LegName(leg) << " joint " << j;
      EXPECT_LT(Anymal().LegUpperBounds(leg)[j] - hi[j], 0.02 * range[j]) << LegName(leg) << " joint " << j;
    }
  }
}

TEST(LimbDatabase, CellsTileTheSamplesAndHoldOnlyTheirFeet) {
  const LimbDatabaseConfig coarse_config = [] {
    LimbDatabaseConfig c = SmallConfig(2000);
    c.octree_resolution = 0.03;
    return c;
  }();
  const LimbDatabase coarse = LimbDatabase::Build(Anymal(), coarse_config);
  for (const LimbDatabase* db : {&Database(), &coarse}) {
    const double res = db->Resolution();
    for (Leg leg : kAllLegs) {
      int next = 0;
      std::set<std::array<long, 3>> centres;
      for (int c = 0; c < db->NumCells(leg); ++c) {
        const LimbCell cell = db->Cell(leg, c);
        EXPECT_EQ(cell.first_sample, next);
        EXPECT_GT(cell.num_samples, 0);
        EXPECT_TRUE(centres.insert({std::lround(cell.centre_B.x() / res * 2), std::lround(cell.centre_B.y() / res * 2),
                                    std::lround(cell.centre_B.z() / res * 2)})
                        .second)
            << "two cells share a centre";
        for (int k = cell.first_sample; k < cell.first_sample + cell.num_samples; ++k) {
          const LimbSample s = db->Sample(leg, k);
          EXPECT_LE((s.foot_B - cell.centre_B).cwiseAbs().maxCoeff(), 0.5 * res + 1e-12);
          EXPECT_EQ(db->CellIndexAt(leg, s.foot_B), c);
          if (k > cell.first_sample) {
            EXPECT_GE(db->Sample(leg, k - 1).score, s.score);
          }
        }
        next += cell.num_samples;
      }
      EXPECT_EQ(next, db->NumSamples(leg));
      // With 1 cm cells most cells hold one or two samples; with 3 cm cells many share.
      EXPECT_LT(db->NumCells(leg), db->NumSamples(leg));
    }
  }
  EXPECT_EQ(Database().CellIndexAt(Leg::kLF, Eigen::Vector3d(5.0, 5.0, 5.0)), -1);
  EXPECT_EQ(Database().CellIndexAt(Leg::kLF, Eigen::Vector3d(1e6, 0.0, 0.0)), -1);
  EXPECT_EQ(Database().CellIndexAt(Leg::kLF, Eigen::Vector3d(NAN, 0.0, 0.0)), -1);
  EXPECT_THROW(Database().Cell(Leg::kLF, Database().NumCells(Leg::kLF)), InputError);
}

TEST(LimbDatabase, ScoresFollowTheWeightedDistanceToTheReference) {
  const LimbDatabase& db = Database();
  const LimbDatabaseConfig config = SmallConfig();
  const Eigen::Vector3d w(config.weight_haa, config.weight_hfe, config.weight_kfe);
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d q_ref = LegJoints(Anymal().ReferenceConfiguration(), leg);
    std::vector<double> raw;
    for (int i = 0; i < db.NumSamples(leg); ++i) {
      raw.push_back(100.0 - std::sqrt(w.dot((db.Sample(leg, i).q - q_ref).cwiseAbs2())));
    }
    const double lo = *std::min_element(raw.begin(), raw.end());
    const double hi = *std::max_element(raw.begin(), raw.end());
    int best = -1;
    double min_score = 1.0, max_score = 0.0;
    for (int i = 0; i < db.NumSamples(leg); ++i) {
      const double s = db.Sample(leg, i).score;
      EXPECT_GE(s, 0.0);
      EXPECT_LE(s, 1.0);
      EXPECT_NEAR(s, (raw[static_cast<std::size_t>(i)] - lo) / (hi - lo), 1e-12);
      if (s > max_score) {
        max_score = s;
        best = i;
      }
      min_score = std::min(min_score, s);
    }
    EXPECT_EQ(max_score, 1.0);
    EXPECT_EQ(min_score, 0.0);
    ASSERT_GE(best, 0);
    EXPECT_EQ(db.Sample(leg, best).q, q_ref) << LegName(leg);
  }
}

TEST(LimbDatabase, WeightsShapeTheScore) {
  LimbDatabaseConfig haa_heavy = SmallConfig(1000);
  haa_heavy.weight_haa = 100.0;
  const LimbDatabase db = LimbDatabase::Build(Anymal(), haa_heavy);
  const LimbDatabase plain = LimbDatabase::Build(Anymal(), SmallConfig(1000));
  // Same draws (same seed), different scores: with a heavy HAA weight, the best-scored samples
  // away from the reference keep HAA close to its reference value.
  const Leg leg = Leg::kRH;
  const double q_ref_haa = LegJoints(Anymal().ReferenceConfiguration(), leg)[0];
  double heavy_haa_dev = 0.0, plain_haa_dev = 0.0;
  int counted = 0;
  std::vector<std::pair<double, int>> heavy_rank, plain_rank;
  for (int i = 0; i < db.NumSamples(leg); ++i) {
    heavy_rank.emplace_back(-db.Sample(leg, i).score, i);
    plain_rank.emplace_back(-plain.Sample(leg, i).score, i);
  }
  std::sort(heavy_rank.begin(), heavy_rank.end());
  std::sort(plain_rank.begin(), plain_rank.end());
  for (std::size_t r = 1; r <= 50; ++r, ++counted) {
    heavy_haa_dev += std::abs(db.Sample(leg, heavy_rank[r].second).q[0] - q_ref_haa);
    plain_haa_dev += std::abs(plain.Sample(leg, plain_rank[r].second).q[0] - q_ref_haa);
  }
  EXPECT_LT(heavy_haa_dev / counted, 0.5 * plain_haa_dev / counted);
}

TEST(LimbDatabase, HorizontalSquareUnderTheHipAtReferenceHeight) {
  const LimbDatabase& db = Database();
  const Eigen::Isometry3d base = Eigen::Translation3d(1.0, -2.0, Anymal().NominalBaseHeight()) *
                                 Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
  const double max_distance = 0.01;
  for (Leg leg : kAllLegs) {
    // The reference feet stand (to the yaml's rounding) on z = 0.
    const Eigen::Vector3d centre = base * Anymal().ReferenceFootPosition(leg);
    ASSERT_NEAR(centre.z(), 0.0, 1e-4);
    const double h = 0.15;
    ConvexSurface square;
    square.vertices = {centre + Eigen::Vector3d(-h, -h, 0), centre + Eigen::Vector3d(h, -h, 0),
                       centre + Eigen::Vector3d(h, h, 0), centre + Eigen::Vector3d(-h, h, 0)};
    const std::vector<FootholdCandidate> candidates = db.Candidates(leg, base, square, max_distance);
    EXPECT_GT(candidates.size(), 20u) << LegName(leg);
    // The visitor sees the same candidates in the same order.
    std::vector<int> visited;
    db.VisitCandidates(leg, base, square.vertices, square.normal, max_distance, 7,
                       [&](const FootholdCandidate& c) {
                         EXPECT_EQ(c.surface, 7);
                         visited.push_back(c.sample);
                       });
    ASSERT_EQ(visited.size(), candidates.size()) << LegName(leg);
    for (std::size_t k = 0; k < visited.size(); ++k) EXPECT_EQ(visited[k], candidates[k].sample);
    auto distance = [&](const Eigen::Vector3d& p) {
      const double dx = std::max(std::abs(p.x() - centre.x()) - h, 0.0);
      const double dy = std::max(std::abs(p.y() - centre.y()) - h, 0.0);
      const double dz = p.z() - centre.z();
      return std::sqrt(dx * dx + dy * dy + dz * dz);
    };
    ExpectCompleteAndSound(leg, base, max_distance, candidates, distance);
    // The reference configuration itself stands in the middle of the square.
    const bool has_reference = std::any_of(candidates.begin(), candidates.end(), [&](const FootholdCandidate& c) {
      return db.Sample(leg, c.sample).q == LegJoints(Anymal().ReferenceConfiguration(), leg);
    });
    EXPECT_TRUE(has_reference) << LegName(leg);
  }
}

TEST(LimbDatabase, RandomTrianglesMatchAnExhaustiveSearch) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Isometry3d base = BasePose();
  int non_empty = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const Leg leg = kAllLegs[static_cast<std::size_t>(trial % 4)];
    const Eigen::Vector3d around = base * (Anymal().ReferenceFootPosition(leg) + 0.15 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const Eigen::Vector3d a = around + 0.25 * Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng));
    const Eigen::Vector3d b = around + 0.25 * Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng));
    const Eigen::Vector3d c = around + 0.25 * Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng));
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    if (normal.norm() < 1e-3) continue;
    const double max_distance = 0.005 + 0.03 * (u(rng) + 1.0);
    const std::vector<FootholdCandidate> candidates =
        Database().Candidates(leg, base, ConvexSurface{{a, b, c}, normal}, max_distance);
    non_empty += candidates.empty() ? 0 : 1;
    ExpectCompleteAndSound(leg, base, max_distance, candidates,
                           [&](const Eigen::Vector3d& p) { return (p - ClosestPointOnTriangle(p, a, b, c)).norm(); });
  }
  EXPECT_GT(non_empty, 12);
}

TEST(LimbDatabase, SteepAndVerticalPolygonsMatchAnExhaustiveSearch) {
  // The query bounds each key column's z range by the polygon's plane; a wall bounds none.
  const Eigen::Isometry3d base = BasePose();
  for (Leg leg : kAllLegs) {
    const Eigen::Vector3d foot = base * Anymal().ReferenceFootPosition(leg);
    for (const double tilt : {1.2, M_PI / 2}) {  // [rad] from horizontal
      const Eigen::Vector3d up = Eigen::AngleAxisd(tilt, base.linear().col(1)) * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d across = (base.linear().col(1) - base.linear().col(1).dot(up) * up).normalized();
      const Eigen::Vector3d along = across.cross(up);  // with `across`, spans the polygon's plane
      const double h = 0.12;
      const Eigen::Vector3d a = foot + 0.05 * up - h * along - h * across;
      const Eigen::Vector3d b = foot + 0.05 * up + h * along - h * across;
      const Eigen::Vector3d c = foot + 0.05 * up + h * along + h * across;
      const Eigen::Vector3d d = foot + 0.05 * up - h * along + h * across;
      const std::vector<FootholdCandidate> candidates =
          Database().Candidates(leg, base, ConvexSurface{{a, b, c, d}, up}, 0.06);
      EXPECT_FALSE(candidates.empty()) << LegName(leg) << " tilt " << tilt;
      ExpectCompleteAndSound(leg, base, 0.06, candidates, [&](const Eigen::Vector3d& p) {
        return std::min((p - ClosestPointOnTriangle(p, a, b, c)).norm(), (p - ClosestPointOnTriangle(p, a, c, d)).norm());
      });
    }
  }
}

TEST(LimbDatabase, SurfacesOutOfReachGiveNoCandidates) {
  const Eigen::Isometry3d base = BasePose();
  auto square_at = [&](const Eigen::Vector3d& c_W, double h) {
    return ConvexSurface{{c_W + Eigen::Vector3d(-h, -h, 0), c_W + Eigen::Vector3d(h, -h, 0),
                          c_W + Eigen::Vector3d(h, h, 0), c_W + Eigen::Vector3d(-h, h, 0)},
                         Eigen::Vector3d::UnitZ()};
  };
  const Eigen::Vector3d base_W = base.translation();
  for (Leg leg : kAllLegs) {
    // Far below the feet, beside the robot, and above the trunk.
    EXPECT_TRUE(Database().Candidates(leg, base, square_at(base_W - Eigen::Vector3d(0, 0, 1.2), 2.0), 0.03).empty());
    EXPECT_TRUE(Database().Candidates(leg, base, square_at(base_W + Eigen::Vector3d(3.0, 0, -0.45), 0.5), 0.03).empty());
    EXPECT_TRUE(Database().Candidates(leg, base, square_at(base_W + Eigen::Vector3d(0, 0, 0.6), 2.0), 0.03).empty());
    // Surfaces at extreme coordinates are handled, not rejected.
    EXPECT_TRUE(Database().Candidates(leg, base, square_at(Eigen::Vector3d(1e6, -1e6, 0), 0.5), 0.03).empty());
  }
  // A ground plane much larger than the leg's reach returns every foot near it: no cap.
  const ConvexSurface ground = square_at(Eigen::Vector3d(base_W.x(), base_W.y(), 0.0), 50.0);
  const auto all = Database().Candidates(Leg::kLF, base, ground, 0.05);
  int expected = 0;
  for (int i = 0; i < Database().NumSamples(Leg::kLF); ++i) {
    expected += std::abs((base * Database().Sample(Leg::kLF, i).foot_B).z()) <= 0.05 ? 1 : 0;
  }
  EXPECT_EQ(static_cast<int>(all.size()), expected);
  EXPECT_GT(expected, 100);
}

TEST(LimbDatabase, AppendCandidatesTagsAndMergesSurfaces) {
  const Eigen::Isometry3d base = BasePose();
  const Eigen::Vector3d foot = base * Anymal().ReferenceFootPosition(Leg::kLH);
  const Eigen::Vector3d n = base.linear() * Eigen::Vector3d::UnitZ();
  const std::vector<Eigen::Vector3d> left = {foot + Eigen::Vector3d(-0.1, 0, 0), foot + Eigen::Vector3d(0, 0, 0),
                                             foot + Eigen::Vector3d(0, 0.1, 0)};
  const std::vector<Eigen::Vector3d> right = {foot + Eigen::Vector3d(0.01, 0, 0), foot + Eigen::Vector3d(0.1, 0, 0),
                                              foot + Eigen::Vector3d(0.1, 0.1, 0)};
  std::vector<FootholdCandidate> merged;
  Database().AppendCandidates(Leg::kLH, base, left, n, 0.02, 3, &merged);
  const std::size_t first = merged.size();
  Database().AppendCandidates(Leg::kLH, base, right, n, 0.02, 7, &merged);
  ASSERT_GT(first, 0u);
  ASSERT_GT(merged.size(), first);
  for (std::size_t i = 0; i < merged.size(); ++i) EXPECT_EQ(merged[i].surface, i < first ? 3 : 7);
  EXPECT_EQ(Database().Candidates(Leg::kLH, base, ConvexSurface{left, n}, 0.02).size(), first);
}

TEST(LimbDatabase, InvalidQueriesThrow) {
  const Eigen::Isometry3d base = BasePose();
  const ConvexSurface ok{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, Eigen::Vector3d::UnitZ()};
  EXPECT_THROW(Database().Candidates(Leg::kLF, base, ok, -0.01), InputError);
  EXPECT_THROW(Database().Candidates(Leg::kLF, base, ok, NAN), InputError);
  EXPECT_THROW(Database().Candidates(Leg::kLF, base, ConvexSurface{{{0, 0, 0}, {1, 0, 0}}, Eigen::Vector3d::UnitZ()}, 0.01),
               InputError);
  EXPECT_THROW(Database().Candidates(Leg::kLF, base, ConvexSurface{ok.vertices, Eigen::Vector3d::Zero()}, 0.01),
               InputError);
  std::vector<FootholdCandidate> out;
  EXPECT_NO_THROW(Database().AppendCandidates(Leg::kLF, base, ok.vertices, ok.normal, 0.0, 0, &out));
  // A sliver without area lying where feet are gives nothing, rather than failing.
  const Eigen::Vector3d foot = base * Anymal().ReferenceFootPosition(Leg::kLF);
  const ConvexSurface sliver{{foot, foot + Eigen::Vector3d(0.1, 0, 0), foot + Eigen::Vector3d(0.2, 0, 0)},
                             Eigen::Vector3d::UnitZ()};
  EXPECT_TRUE(Database().Candidates(Leg::kLF, base, sliver, 0.05).empty());
}

TEST(LimbDatabase, SamplesInBoxMatchesAnExhaustiveSearch) {
  const Eigen::Vector3d lo(0.25, 0.1, -0.5), hi(0.45, 0.35, -0.35);
  const std::vector<int> in_box = Database().SamplesInBox(Leg::kLF, lo, hi);
  std::vector<int> expected;
  for (int i = 0; i < Database().NumSamples(Leg::kLF); ++i) {
    const Eigen::Vector3d p = Database().Sample(Leg::kLF, i).foot_B;
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) expected.push_back(i);
  }
  EXPECT_EQ(in_box, expected);
  EXPECT_GT(expected.size(), 50u);
  EXPECT_TRUE(Database().SamplesInBox(Leg::kLF, hi, lo).empty());
}

TEST(LimbDatabase, SameSeedSameDatabaseOtherSeedOtherDatabase) {
  const LimbDatabaseConfig config = SmallConfig(1500);
  const LimbDatabase a = LimbDatabase::Build(Anymal(), config);
  const LimbDatabase b = LimbDatabase::Build(Anymal(), config);
  LimbDatabaseConfig other = config;
  other.seed = config.seed + 1;
  const LimbDatabase c = LimbDatabase::Build(Anymal(), other);
  for (Leg leg : kAllLegs) {
    ASSERT_EQ(a.NumCells(leg), b.NumCells(leg));
    EXPECT_EQ(a.Draws(leg), b.Draws(leg));
    for (int i = 0; i < a.NumSamples(leg); ++i) {
      EXPECT_EQ(a.Sample(leg, i).q, b.Sample(leg, i).q);
      EXPECT_EQ(a.Sample(leg, i).foot_B, b.Sample(leg, i).foot_B);
      EXPECT_EQ(a.Sample(leg, i).score, b.Sample(leg, i).score);
    }
    for (int k = 0; k < a.NumCells(leg); ++k) {
      EXPECT_EQ(a.Cell(leg, k).centre_B, b.Cell(leg, k).centre_B);
      EXPECT_EQ(a.Cell(leg, k).num_samples, b.Cell(leg, k).num_samples);
    }
    int differing = 0;
    for (int i = 0; i < a.NumSamples(leg); ++i) differing += a.Sample(leg, i).q != c.Sample(leg, i).q ? 1 : 0;
    EXPECT_GT(differing, a.NumSamples(leg) / 2) << LegName(leg);
  }
  // Legs draw from distinct streams: the RF hip angles are not the LF ones mirrored.
  std::set<double> lf_haa;
  for (int i = 0; i < a.NumSamples(Leg::kLF); ++i) lf_haa.insert(a.Sample(Leg::kLF, i).q[0]);
  int mirrored = 0;
  for (int i = 0; i < a.NumSamples(Leg::kRF); ++i) mirrored += lf_haa.count(-a.Sample(Leg::kRF, i).q[0]) ? 1 : 0;
  EXPECT_LE(mirrored, 1);  // the reference stance is symmetric
}

TEST(LimbDatabase, MemoryIsDominatedByTheSampleArrays) {
  const LimbDatabase& db = Database();
  const std::size_t arrays = 4u * kSamples * 7u * sizeof(double);
  EXPECT_GE(db.MemoryBytes(), arrays);
  EXPECT_LT(db.MemoryBytes(), 6 * arrays);
}

}  // namespace
}  // namespace rbcp
