#pragma once
/// What every stage of a contact-planning query works with: the robot, the limb database, the
/// configuration and the terrain (read only), and the equilibrium LP workspace, the work counters
/// and the time budget (written).

#include <array>
#include <atomic>
#include <chrono>
#include <optional>
#include <vector>

#include "rbcp/collision/robot_terrain_collision.h"
#include "rbcp/stance/stance_checker.h"
#include "rbcp/contact_planner/contact_planner.h"
#include "rbcp/equilibrium/static_equilibrium.h"
#include "surface_geometry.h"

namespace rbcp {
class LimbDatabase;
class RobotModel;
}  // namespace rbcp

namespace rbcp::contact_planner_detail {

/// The wall-clock budget of a query. The clock is read only here, to report the planning time
/// and to stop the search.
class TimeBudget {
 public:
  /// Starts the clock with `budget_s` [s] to spend.
  void Start(double budget_s) {
    start_ = std::chrono::steady_clock::now();
    budget_s_ = budget_s;
    exhausted_ = false;
    calls_ = 0;
  }
  /// Seconds since Start().
  double Elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  /// True once more than the budget has elapsed (or the cancel flag is set), and from then on
  /// until the next Start().
  bool Exhausted() {
    if (exhausted_) return true;
    if (cancel_ != nullptr && cancel_->load(std::memory_order_relaxed)) exhausted_ = true;
    // The clock is read every kClockStride calls: the search asks for every candidate it tests.
    if (calls_++ % kClockStride == 0 && Elapsed() > budget_s_) exhausted_ = true;
    return exhausted_;
  }
  /// The same budget (its start and whether it is exhausted) for another search, which it also
  /// ends once *flag is set (a search whose answer is no longer needed).
  TimeBudget CancelledBy(const std::atomic<bool>* flag) const {
    TimeBudget b = *this;
    b.cancel_ = flag;
    b.calls_ = 0;  // its first check reads the clock
    return b;
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double budget_s_ = 0.0;
  static constexpr unsigned kClockStride = 16;
  bool exhausted_ = false;
  unsigned calls_ = 0;
  const std::atomic<bool>* cancel_ = nullptr;
};

/// A step the search is not to take again (the plan found with it failed the dynamic walk's
/// check): `leg` to `foothold`, from the stance with its feet at `feet_before`, or from any stance
/// (a foothold where the leg's stance fails, whatever the other feet).
struct AvoidedStep {
  int leg = -1;
  Eigen::Vector3d foothold = Eigen::Vector3d::Zero();
  std::optional<std::array<Eigen::Vector3d, kNumLegs>> feet_before;

  /// Two footholds (or stances' feet) closer than this are the same [m].
  static constexpr double kSameM = 0.03;

  /// The step of `after` (its moving leg) from `before`; from any stance if not `from_before`.
  static AvoidedStep Of(const WholeBodyState& before, const WholeBodyState& after, bool from_before = true) {
    AvoidedStep s;
    s.leg = after.moving_leg;
    s.foothold = after.feet[static_cast<std::size_t>(s.leg)].position;
    if (from_before) {
      s.feet_before.emplace();
      for (std::size_t i = 0; i < kNumLegs; ++i) (*s.feet_before)[i] = before.feet[i].position;
    }
    return s;
  }
  bool operator==(const AvoidedStep& o) const {
    if (leg != o.leg || (foothold - o.foothold).norm() > kSameM || feet_before.has_value() != o.feet_before.has_value()) {
      return false;
    }
    return !feet_before || SameFeet(*feet_before, *o.feet_before);
  }
  /// Whether the step from `before` to `after` is this one.
  bool Is(const WholeBodyState& before, const WholeBodyState& after) const {
    return after.moving_leg == leg && *this == Of(before, after, feet_before.has_value());
  }

 private:
  static bool SameFeet(const std::array<Eigen::Vector3d, kNumLegs>& a, const std::array<Eigen::Vector3d, kNumLegs>& b) {
    for (std::size_t i = 0; i < kNumLegs; ++i) {
      if ((a[i] - b[i]).norm() > kSameM) return false;
    }
    return true;
  }
};

/// Whether the step from `before` to `after` is one of `avoided`.
inline bool IsAvoided(const std::vector<AvoidedStep>& avoided, const WholeBodyState& before,
                      const WholeBodyState& after) {
  for (const AvoidedStep& s : avoided) {
    if (s.Is(before, after)) return true;
  }
  return false;
}

/// The planner's robot, database, configuration, stance rules and terrain, shared by reference
/// with every stage. Through its last four members a stage writes the LP workspace, counts its
/// work, checks the budget and keeps its centre-of-mass scratch; a thread has its own of those.
struct PlannerContext {
  const RobotModel& robot;
  const LimbDatabase& db;
  const EquilibriumConfig& eq_config;
  const ContactPlannerConfig& config;
  /// The stance rules the controller walks by: support margin, torques, collision with the
  /// clearances (TerrainCollision) and exact (ExactCollision), the swing path.
  const StanceChecker& stance;
  const std::vector<ConvexPolygon3d>& surfaces; ///< the contact surfaces, as given to SetTerrain
  const std::vector<AvoidedStep>& avoided;       ///< steps this query's searches do not take
  StaticEquilibrium& equilibrium;
  ContactPlanStats& stats;
  TimeBudget& budget;
  BodyPoseData& body_poses;  ///< the centre-of-mass scratch of the thread running this context
};

}  // namespace rbcp::contact_planner_detail
