#pragma once
/// The path of a swinging foot: it rises vertically from its lift-off point, crosses at an apex
/// height to above its new foothold and descends vertically onto it (to touchdown_depth_m below
/// the foothold, so that it touches down), each part blended smoothly into the next: the height
/// reaches the apex over the first 40 % of the swing while the horizontal motion runs from 10 %
/// to 90 %. The apex is raised until the path clears the terrain under it (and, when a check is
/// given, until the whole leg does); if raising alone does not clear the leg, the path also bows
/// sideways towards the body (a lifted foot under an abducted leg swings its knee outwards, into
/// a wall beside the robot; drawing the foot in keeps the leg upright), and then back against the
/// swing direction (a foot rising under a fixed hip bends its knee forwards, into the edge of a
/// higher foothold ahead; drawn back, the leg stays straighter until the knee is above it).

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "rbcp/scenario/scenario.h"
#include "rbcp/stance/stance_config.h"

namespace rbcp {

/// How far SwingTrajectory::Plan searches.
enum class SwingSearch {
  /// Every apex and bow until a path passes every check; without one, the path with the fewest
  /// failing samples.
  kFewestFailures,
  /// The first path that passes every check, each candidate given up at its first failing
  /// sample (a planner that only needs a clear path, or none).
  kFirstClear,
};

class SwingTrajectory {
 public:
  SwingTrajectory() = default;

  /// A check of a foot position along the path [m, world]: true when the leg is clear there.
  using LegCheck = std::function<bool(const Eigen::Vector3d& foot_W)>;

  /// Plans the swing from start_W to target_W (contact points, world frame [m]). With a terrain,
  /// the apex is raised in 2 cm steps (up to 0.3 m) until the foot (a sphere of radius
  /// foot_radius_m above its contact point) stays terrain_clearance_m above the terrain over the
  /// middle of the path and never enters it near the ends, and `leg_clear` (if given) holds at
  /// every sample. The lowest apex that satisfies everything is kept; if none does, the lowest one
  /// with the fewest leg collisions.
  /// `inward_W`: horizontal direction towards the body, along which the path may bow (in 3 cm
  /// steps up to 9 cm at the apex) when the leg check fails at every apex; zero: never. Then it
  /// may bow back against the swing direction, in the same steps.
  /// `leg_preferred` (if given, with leg_clear): a check the path passes where it can. A path
  /// that passes every check is kept as above; otherwise the one with the fewest leg collisions,
  /// and among those the fewest samples (where leg_clear holds) that fail leg_preferred
  /// (kFewestFailures; with kFirstClear such a path's counts are not meaningful).
  static SwingTrajectory Plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W,
                              const TerrainHeightMap* terrain, double foot_radius_m, const SwingPathConfig& config,
                              const LegCheck& leg_clear = {}, const Eigen::Vector2d& inward_W = Eigen::Vector2d::Zero(),
                              const LegCheck& leg_preferred = {}, SwingSearch search = SwingSearch::kFewestFailures);

  /// The path from start_W to target_W with a given apex height [m, world z] (at least the
  /// higher foothold's) and sideways bow at the apex [m, world xy], as Plan chose them: a plan's
  /// swing, walked as planned. Its clearance is not known (NaN).
  static SwingTrajectory Given(const Eigen::Vector3d& start_W, const Eigen::Vector3d& target_W, double apex_z,
                               const Eigen::Vector2d& bow_W, const SwingPathConfig& config);

  /// The same path (apex, bow, end, duration) started at start_W instead: for a foot that stands
  /// a little off the foothold the path was planned from.
  SwingTrajectory StartingAt(const Eigen::Vector3d& start_W) const {
    SwingTrajectory s = *this;
    s.start_ = start_W;
    return s;
  }

  /// The same path timed for `config`'s speed and shortest swing.
  SwingTrajectory Retimed(const SwingPathConfig& config) const {
    SwingTrajectory s = *this;
    s.SetDuration(config);
    return s;
  }

  /// The same path lasting duration_s (> 0): a swing timed by its plan.
  SwingTrajectory Lasting(double duration_s) const {
    SwingTrajectory s = *this;
    s.duration_s_ = duration_s;
    return s;
  }

  double Duration() const { return duration_s_; }
  /// Phase in [0, 1] after t [s] of swing.
  double Phase(double t) const;
  /// Contact point position and velocity after t [s] of swing (held at the end after Duration()).
  Eigen::Vector3d Position(double t) const;
  Eigen::Vector3d Velocity(double t) const;
  /// Its acceleration [m/s^2] (zero before the start and after the end).
  Eigen::Vector3d Acceleration(double t) const;

  /// The foot positions at which Plan checks the leg [m, world]: every other of its path samples,
  /// once the foot is 2 cm above the foothold it rises from, or then descends to.
  std::vector<Eigen::Vector3d> LegCheckPoints() const;

  /// Least height of the foot above the terrain over the middle of the swing [m] (+inf without terrain).
  double Clearance() const { return clearance_m_; }
  /// Whether the path keeps the foot terrain_clearance_m above the terrain over its middle and out
  /// of it near its ends (true without a terrain).
  bool TerrainClear() const { return terrain_clear_; }
  /// Height of the apex [m, world z].
  double Apex() const { return apex_z_; }
  /// Samples at which `leg_clear` failed (0 when it held everywhere or was not given).
  int LegCollisions() const { return leg_collisions_; }
  /// Samples at which `leg_clear` held and `leg_preferred` failed.
  int PreferredMisses() const { return preferred_misses_; }
  /// Sideways bow of the path at the apex [m, world xy].
  const Eigen::Vector2d& Bow() const { return bow_; }

 private:
  /// Position and d/ds at path parameter s in [0, 1].
  Eigen::Vector3d At(double s, Eigen::Vector3d* ds = nullptr) const;
  /// The duration that keeps every part of the path below config.speed_mps.
  void SetDuration(const SwingPathConfig& config);

  // The steps of Plan, on a candidate path.
  struct Checks;
  struct PathTerrain;
  /// The terrain under the path's samples (their xy do not depend on the apex).
  PathTerrain TerrainUnder(const Checks& checks) const;
  /// Sets the clearance and whether the path at its apex clears the terrain; returns the latter.
  bool CheckTerrain(const PathTerrain& under, const Checks& checks);
  /// Counts the samples at which the leg checks fail (only up to the first with first_clear).
  void CheckLeg(const Checks& checks);
  /// Raises the apex from base_apex in kRiseStep steps, keeping in `best` the lowest path that
  /// clears the terrain with the fewest leg failures so far; true when one passes every check.
  bool RaiseApex(double base_apex, const Checks& checks, std::optional<SwingTrajectory>& best);

  Eigen::Vector3d start_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_ = Eigen::Vector3d::Zero();
  double target_z_ = 0.0;  // the foothold's height (the path ends touchdown_depth_m below it)
  double apex_z_ = 0.0;
  Eigen::Vector2d bow_ = Eigen::Vector2d::Zero();
  double duration_s_ = 1.0;
  double clearance_m_ = 0.0;
  int leg_collisions_ = 0;
  int preferred_misses_ = 0;
  bool terrain_clear_ = true;
};

}  // namespace rbcp
