#pragma once
/// What every stage of a contact-planning query works with: the robot, the limb database, the
/// configuration and the terrain (read only), and the equilibrium LP workspace, the work counters
/// and the time budget (written).

#include <atomic>
#include <chrono>
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
  StaticEquilibrium& equilibrium;
  ContactPlanStats& stats;
  TimeBudget& budget;
  BodyPoseData& body_poses;  ///< the centre-of-mass scratch of the thread running this context
};

}  // namespace rbcp::contact_planner_detail
