#include "rbcp/stance/swing_trajectory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>


namespace rbcp {
namespace {

constexpr int kSamples = 40;
constexpr double kMaxRise = 0.3;     // [m] highest extra lift tried
constexpr double kRiseStep = 0.02;   // [m]
constexpr double kRiseEnd = 0.4;     // the height reaches the apex over s in [0, kRiseEnd] (and back)
constexpr double kCrossBegin = 0.1;  // the horizontal motion runs over s in [kCrossBegin, 1 - kCrossBegin]
constexpr double kEndSkip = 0.97;    // beyond this the path dips below the foothold on purpose
constexpr int kBows = 4;             // sideways bows tried: 0, 3, 6, 9 cm
constexpr double kBowStep = 0.03;    // [m]
constexpr int kPatience = 8;         // rises in a row without fewer leg collisions before the next bow

double SmoothStep(double u, double* rate = nullptr) {
  if (u <= 0.0 || u >= 1.0) {
    if (rate) *rate = 0.0;
    return u <= 0.0 ? 0.0 : 1.0;
  }
  if (rate) *rate = 6.0 * u * (1.0 - u);
  return u * u * (3.0 - 2.0 * u);
}

/// The vertical gap [m] between the foot sphere (radius r, resting on a contact point at height z
/// above xy) and the terrain under it is z + SphereGapOffset(terrain, xy, r): sampled on rings
/// around the sphere's centre; +inf with no terrain below.
double SphereGapOffset(const TerrainHeightMap& terrain, const Eigen::Vector2d& xy, double r) {
  // The eight directions of a ring, k * 45 degrees.
  static const std::array<Eigen::Vector2d, 8> kRing = [] {
    std::array<Eigen::Vector2d, 8> ring;
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4.0;
      ring[static_cast<std::size_t>(k)] = Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    return ring;
  }();
  double offset = std::numeric_limits<double>::infinity();
  for (double d : {0.0, 0.5 * r, 0.9 * r}) {
    const double rise = r - std::sqrt(r * r - d * d);  // sphere surface above its lowest point
    for (int k = 0; k < (d > 0.0 ? 8 : 1); ++k) {
      const std::optional<double> h = terrain.At(xy + d * kRing[static_cast<std::size_t>(k)]);
      if (h) offset = std::min(offset, rise - *h);
    }
  }
  return offset;
}

/// The bows Plan tries: none, then (with a leg check) towards the body, then back against the
/// swing direction (a knee that points ahead, into the riser of a higher foothold, stays behind it
/// while the foot rises), each in kBowStep steps.
std::vector<Eigen::Vector2d> Bows(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                  const Eigen::Vector2d& inward_W, bool leg_checked) {
  std::vector<Eigen::Vector2d> bows = {Eigen::Vector2d::Zero()};
  if (!leg_checked) return bows;
  const Eigen::Vector2d ahead = (target_W - start_W).head<2>();
  for (const Eigen::Vector2d& direction : {Eigen::Vector2d(inward_W), Eigen::Vector2d(-ahead)}) {
    if (direction.norm() < 1e-9) continue;
    for (int k = 1; k < kBows; ++k) bows.push_back(kBowStep * k * direction.normalized());
  }
  return bows;
}

/// Fewer leg collisions first, then fewer samples that miss the preferred check.
bool FewerLegFailures(const SwingTrajectory& a, const SwingTrajectory& b) {
  return std::make_pair(a.LegCollisions(), a.PreferredMisses()) < std::make_pair(b.LegCollisions(), b.PreferredMisses());
}

}  // namespace

/// What Plan checks a candidate path against.
struct SwingTrajectory::Checks {
  const TerrainHeightMap* terrain;  ///< nullptr: no terrain check
  Eigen::Vector3d target_W;         ///< the foothold [m, world]
  double foot_radius_m;
  double terrain_clearance_m;
  const LegCheck& leg_clear;
  const LegCheck& leg_preferred;
  bool first_clear;  ///< SwingSearch::kFirstClear
};

/// The terrain under a candidate path's samples 1 .. kSamples - 1 (index 0 unused).
struct SwingTrajectory::PathTerrain {
  std::array<double, kSamples> offset;  ///< SphereGapOffset under the sample (+inf: none)
  /// The sample is within foot_radius_m + 2 cm (horizontally) of the new foothold.
  std::array<bool, kSamples> near_end{};
  /// The sample is farther than that from both footholds.
  std::array<bool, kSamples> away{};
};

Eigen::Vector3d SwingTrajectory::At(double s, Eigen::Vector3d* ds) const {
  double h_rate = 0.0;
  const double h = SmoothStep((s - kCrossBegin) / (1.0 - 2.0 * kCrossBegin), &h_rate);
  h_rate /= (1.0 - 2.0 * kCrossBegin);
  Eigen::Vector3d p;
  p.head<2>() = start_.head<2>() + h * (end_.head<2>() - start_.head<2>());
  // lift in [0, 1]: how far up the foot is (0 at the footholds, 1 at the apex).
  double lift = 0.0, lift_rate = 0.0;
  if (s <= 0.5) {
    lift = SmoothStep(s / kRiseEnd, &lift_rate);
    lift_rate /= kRiseEnd;
    p.z() = start_.z() + (apex_z_ - start_.z()) * lift;
  } else {
    lift = SmoothStep((1.0 - s) / kRiseEnd, &lift_rate);
    lift_rate /= -kRiseEnd;
    p.z() = end_.z() + (apex_z_ - end_.z()) * lift;
  }
  p.head<2>() += lift * bow_;
  if (ds) {
    ds->head<2>() = h_rate * (end_.head<2>() - start_.head<2>()) + lift_rate * bow_;
    ds->z() = (s <= 0.5 ? apex_z_ - start_.z() : apex_z_ - end_.z()) * lift_rate;
  }
  return p;
}

SwingTrajectory::PathTerrain SwingTrajectory::TerrainUnder(const Checks& checks) const {
  // The samples' xy do not depend on the apex: the terrain is queried once per bow.
  PathTerrain under;
  for (int k = 1; k < kSamples; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    const Eigen::Vector2d xy = At(static_cast<double>(k) / kSamples).head<2>();
    // Away from its footholds the foot keeps the clearance; next to them it only must not sink
    // into the terrain (it rises from and descends to a surface there; the last part of the path
    // dips below the new foothold on purpose).
    const double near = checks.foot_radius_m + 0.02;
    under.near_end[i] = (xy - checks.target_W.head<2>()).norm() <= near;
    under.away[i] = (xy - start_.head<2>()).norm() > near && !under.near_end[i];
    under.offset[i] = checks.terrain != nullptr ? SphereGapOffset(*checks.terrain, xy, checks.foot_radius_m)
                                                : std::numeric_limits<double>::infinity();
  }
  return under;
}

bool SwingTrajectory::CheckTerrain(const PathTerrain& under, const Checks& checks) {
  double middle = std::numeric_limits<double>::infinity();
  bool enters = false;
  for (int k = 1; k < kSamples; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    const double u = static_cast<double>(k) / kSamples;
    if (u > kEndSkip) break;
    if (!std::isfinite(under.offset[i])) continue;
    const Eigen::Vector3d p = At(u);
    const double gap = (under.near_end[i] ? std::max(p.z(), checks.target_W.z()) : p.z()) + under.offset[i];
    if (under.away[i]) middle = std::min(middle, gap);
    if (gap < (under.away[i] ? 0.005 : -0.003)) enters = true;
  }
  clearance_m_ = middle;
  terrain_clear_ = !enters && middle >= checks.terrain_clearance_m;
  return terrain_clear_;
}

void SwingTrajectory::CheckLeg(const Checks& checks) {
  leg_collisions_ = 0;
  preferred_misses_ = 0;
  for (const Eigen::Vector3d& p : checks.leg_clear ? LegCheckPoints() : std::vector<Eigen::Vector3d>{}) {
    if (!checks.leg_clear(p)) {
      leg_collisions_ += 1;
    } else if (checks.leg_preferred && !checks.leg_preferred(p)) {
      preferred_misses_ += 1;
    } else {
      continue;
    }
    if (checks.first_clear) break;
  }
}

bool SwingTrajectory::RaiseApex(double base_apex, const Checks& checks, std::optional<SwingTrajectory>& best) {
  const PathTerrain under = TerrainUnder(checks);
  int worse = 0;  // rises in a row that did not reduce the leg's collisions
  for (double rise = 0.0; rise <= kMaxRise + 1e-9 && worse < kPatience; rise += kRiseStep) {
    apex_z_ = base_apex + rise;
    const bool terrain_ok = CheckTerrain(under, checks);
    if (checks.first_clear && !terrain_ok) continue;  // a higher apex may clear it
    CheckLeg(checks);
    if (terrain_ok && leg_collisions_ == 0 && preferred_misses_ == 0) {
      best = *this;
      return true;
    }
    if (terrain_ok && best && !FewerLegFailures(*this, *best)) ++worse;
    if (terrain_ok && (!best || FewerLegFailures(*this, *best))) {
      best = *this;
      worse = 0;
    }
  }
  return false;
}

SwingTrajectory SwingTrajectory::Plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                      const TerrainHeightMap* terrain, double foot_radius_m, const SwingPathConfig& config,
                                      const LegCheck& leg_clear, const Eigen::Vector2d& inward_W,
                                      const LegCheck& leg_preferred, SwingSearch search) {
  SwingTrajectory s;
  s.start_ = start_W;
  s.end_ = target_W - Eigen::Vector3d(0, 0, config.touchdown_depth_m);
  s.target_z_ = target_W.z();
  const double base_apex = std::max(start_W.z(), target_W.z()) + config.height_m;
  s.apex_z_ = base_apex;
  s.clearance_m_ = std::numeric_limits<double>::infinity();
  const bool check_terrain = terrain != nullptr && !terrain->Empty();
  if (check_terrain || leg_clear) {
    const Checks checks{check_terrain ? terrain : nullptr, target_W, foot_radius_m, config.terrain_clearance_m,
                        leg_clear, leg_preferred, search == SwingSearch::kFirstClear};
    // Each bow raises the apex from the lowest; the first path that passes every check ends the search.
    std::optional<SwingTrajectory> best;
    for (const Eigen::Vector2d& bow : Bows(start_W, target_W, inward_W, static_cast<bool>(leg_clear))) {
      SwingTrajectory candidate = s;
      candidate.bow_ = bow;
      if (candidate.RaiseApex(base_apex, checks, best)) break;
    }
    if (best) {
      s = *best;
    } else {
      s.apex_z_ = base_apex + kMaxRise;
      s.terrain_clear_ = false;
    }
  }
  s.SetDuration(config);
  return s;
}

SwingTrajectory SwingTrajectory::Given(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                                       double apex_z, const Eigen::Vector2d& bow_W, const SwingPathConfig& config) {
  SwingTrajectory s;
  s.start_ = start_W;
  s.end_ = target_W - Eigen::Vector3d(0, 0, config.touchdown_depth_m);
  s.target_z_ = target_W.z();
  s.apex_z_ = std::max(apex_z, std::max(start_W.z(), target_W.z()));
  s.bow_ = bow_W;
  s.clearance_m_ = std::numeric_limits<double>::quiet_NaN();
  s.SetDuration(config);
  return s;
}

void SwingTrajectory::SetDuration(const SwingPathConfig& config) {
  // No part of the path faster than speed_mps at its peak. The rise and the descent each take
  // 40 % of the swing and the crossing 80 %, all on smooth steps (peak 1.5 x mean).
  const double up = std::max(apex_z_ - start_.z(), apex_z_ - end_.z());
  const double across = (end_.head<2>() - start_.head<2>()).norm();
  duration_s_ = std::max({config.min_duration_s, 1.5 * std::hypot(up, bow_.norm()) / (kRiseEnd * config.speed_mps),
                          1.5 * across / ((1.0 - 2.0 * kCrossBegin) * config.speed_mps)});
}

std::vector<Eigen::Vector3d> SwingTrajectory::LegCheckPoints() const {
  // 2 cm above the foothold it rises from, then above the one it descends to: at its footholds
  // the plan's own stances hold, and a foot on the ground touches it. From a lower foothold the
  // knee passes the riser of the higher one on the way up.
  std::vector<Eigen::Vector3d> points;
  for (int k = 2; k < kSamples; k += 2) {
    const double u = static_cast<double>(k) / kSamples;
    if (u > kEndSkip) break;
    const Eigen::Vector3d p = At(u);
    if (p.z() > (u <= 0.5 ? start_.z() : target_z_) + 0.02) points.push_back(p);
  }
  return points;
}

double SwingTrajectory::Phase(double t) const { return std::clamp(t / duration_s_, 0.0, 1.0); }

Eigen::Vector3d SwingTrajectory::Position(double t) const { return At(Phase(t)); }

Eigen::Vector3d SwingTrajectory::Velocity(double t) const {
  if (t <= 0.0 || t >= duration_s_) return Eigen::Vector3d::Zero();
  Eigen::Vector3d ds;
  At(Phase(t), &ds);
  return ds / duration_s_;
}

Eigen::Vector3d SwingTrajectory::Acceleration(double t) const {
  if (t <= 0.0 || t >= duration_s_) return Eigen::Vector3d::Zero();
  const double h = 1e-3 * duration_s_;
  return (Velocity(t + h) - Velocity(t - h)) / (2.0 * h);
}

}  // namespace rbcp
