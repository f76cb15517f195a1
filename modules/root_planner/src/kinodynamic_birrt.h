#pragma once
// OMPL side of root planning (private to the library): the state space, the validity checker and
// motion validator built on the reachability condition and the double-integrator steering, the
// surface sampler, the bidirectional RRT planner and its path type.

#include <ompl/base/MotionValidator.h>
#include <ompl/base/Path.h>
#include <ompl/base/Planner.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/StateSpace.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/util/RandomNumbers.h>

#include <optional>
#include <limits>
#include <vector>

#include "rbcp/core/affordance_surface.h"
#include "rbcp/root_planner/double_integrator.h"
#include "rbcp/root_planner/reachability_checker.h"
#include "rbcp/root_planner/root_path.h"

namespace rbcp::detail {

namespace ob = ompl::base;

/// (position [m], velocity [m/s], rest yaw [rad]) of the base. The distance is the lower bound of
/// the steering time from the first state to the second (not symmetric).
class RootStateSpace : public ob::CompoundStateSpace {
 public:
  explicit RootStateSpace(const KinodynamicLimits& limits);

  void SetPositionBounds(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

  static PointState Point(const ob::State* state);
  static double RestYaw(const ob::State* state);
  static void Set(ob::State* state, const PointState& point, double rest_yaw);

  double distance(const ob::State* from, const ob::State* to) const override;
  const KinodynamicLimits& Limits() const { return limits_; }

 private:
  KinodynamicLimits limits_;
};

/// Parameters shared by the OMPL components.
struct SteeringSettings {
  KinodynamicLimits limits;
  YawModel yaw;
  double time_step = 0.05;
  int validation_substeps = 2;
  double max_piece_duration = 50.0;
  double max_yaw_rate = 15.0;  ///< [rad/s] bound of the yaw change between validation samples
};

/// A state is valid when the base pose (yaw from the velocity and rest yaw) satisfies the
/// reachability condition. Counts its queries.
class ReachabilityValidityChecker : public ob::StateValidityChecker {
 public:
  ReachabilityValidityChecker(const ob::SpaceInformationPtr& si, ReachabilityChecker* checker, YawModel yaw);
  bool isValid(const ob::State* state) const override;
  bool IsValid(const Eigen::Vector3d& p, const Eigen::Vector3d& v, double rest_yaw) const;
  double Yaw(const Eigen::Vector3d& v, double rest_yaw) const;
  long Checks() const { return checks_; }

 private:
  ReachabilityChecker* checker_;
  YawModel yaw_;
  mutable long checks_ = 0;
};

/// Steers with the double integrator (durations on the time_step grid) and validates along the
/// time parametrisation every time_step / validation_substeps: each sample must satisfy the
/// reachability condition and the yaw may change by at most max_yaw_rate times the sampling
/// interval from the previous sample.
class KinodynamicMotionValidator : public ob::MotionValidator {
 public:
  KinodynamicMotionValidator(const ob::SpaceInformationPtr& si, const ReachabilityValidityChecker* validity,
                             SteeringSettings settings);

  /// The steered piece between two states, the rest yaw going from the first state's to the
  /// second's; nullopt when steering fails or takes longer than max_piece_duration.
  std::optional<RootSegment> Steer(const PointState& from, double rest_from, const PointState& to,
                                   double rest_to) const;
  /// The largest multiple of time_step up to which every validation sample of the segment is
  /// valid (its start is taken as valid).
  double ValidPrefix(const RootSegment& segment) const;
  /// The smallest multiple of time_step from which every validation sample is valid up to the
  /// end (its end is taken as valid); the segment's duration when none.
  double ValidSuffix(const RootSegment& segment) const;
  /// Every validation sample valid (both ends included).
  bool IsValid(const RootSegment& segment) const;

  bool checkMotion(const ob::State* s1, const ob::State* s2) const override;
  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last_valid) const override;

  const SteeringSettings& Settings() const { return settings_; }

 private:
  RootPathSample SampleAt(const RootSegment& segment, long k) const;
  bool Valid(const RootPathSample& s) const;
  bool YawStepValid(const RootPathSample& a, const RootPathSample& b) const;
  long SampleCount(const RootSegment& segment) const;

  const ReachabilityValidityChecker* validity_;
  SteeringSettings settings_;
};

/// Parameters of the surface sampler.
struct SamplerSettings {
  double standing_height = 0.45;            ///< [m] base height above the contact point
  double area_weighted_probability = 0.3;
  double height_offset_min = -0.05;
  double height_offset_max = 0.05;
  double zero_velocity_probability = 0.3;
  int attempts = 20;
  int repair_moves = 8;                     ///< vertical moves to repair an invalid sample
  double repair_step = 0.03;                ///< [m] first vertical move of a repair
  double rest_yaw = 0.0;                    ///< rest yaw of samples (for their validity test)
  bool vertical_fixed = false;
  double fixed_height = 0.0;                ///< base height when vertical_fixed
};

/// Samples base states above the contact surfaces: a surface (area-weighted or uniform), a
/// uniform point of it, raised by the standing height. An invalid sample is repaired by moving
/// it vertically (up while the trunk collides, down while a leg reaches no surface, halving the
/// bracket once both are known), then redrawn if still invalid (bounded attempts).
class SurfaceStateSampler : public ob::StateSampler {
 public:
  SurfaceStateSampler(const ob::StateSpace* space, const std::vector<AffordanceSurface>* surfaces,
                      const ReachabilityValidityChecker* validity, ReachabilityChecker* checker,
                      SamplerSettings settings, unsigned seed);

  void sampleUniform(ob::State* state) override;
  void sampleUniformNear(ob::State* state, const ob::State* near, double distance) override;
  void sampleGaussian(ob::State* state, const ob::State* mean, double std_dev) override;

 private:
  void SampleOnce(ob::State* state);
  bool Repair(ob::State* state);

  const std::vector<AffordanceSurface>* surfaces_;
  const ReachabilityValidityChecker* validity_;
  ReachabilityChecker* checker_;
  SamplerSettings settings_;
  std::vector<double> surface_area_cdf_;
  std::vector<std::vector<double>> triangle_area_cdf_;  ///< fan triangles of each surface
  double v_max_ = 0.0;
};

/// An OMPL path holding a time-parametrised root path; its length is its duration [s].
class RootTrajectoryPath : public ob::Path {
 public:
  RootTrajectoryPath(const ob::SpaceInformationPtr& si, RootPath path, const KinodynamicMotionValidator* validator);
  double length() const override { return path_.Duration(); }
  ob::Cost cost(const ob::OptimizationObjectivePtr& objective) const override;
  bool check() const override;
  void print(std::ostream& out) const override;
  const RootPath& Path() const { return path_; }

 private:
  RootPath path_;
  const KinodynamicMotionValidator* validator_;
};

/// Counters of one solve.
struct BiRrtStats {
  int iterations = 0;
  int start_tree_states = 0;
  int goal_tree_states = 0;
};

/// Kinodynamic bidirectional RRT (Fernbach et al. 2017 as used by RB-PRM): both trees extend
/// towards the same sample with the steering method, keeping the valid prefix (start tree) or
/// suffix (goal tree); then they try to meet. The start tree's states keep the start state's rest
/// yaw, the goal tree's the goal's; the piece joining them interpolates it.
class KinodynamicBiRrt : public ob::Planner {
 public:
  KinodynamicBiRrt(const ob::SpaceInformationPtr& si, const KinodynamicMotionValidator* validator,
                   SamplerSettings sampler_settings, const std::vector<AffordanceSurface>* surfaces,
                   const ReachabilityValidityChecker* validity, ReachabilityChecker* checker, unsigned seed);
  ~KinodynamicBiRrt() override;

  ob::PlannerStatus solve(const ob::PlannerTerminationCondition& ptc) override;
  void clear() override;
  void getPlannerData(ob::PlannerData& data) const override;

  const BiRrtStats& Stats() const { return stats_; }
  /// The search stops after this many iterations (and when the termination condition says so).
  void SetMaxIterations(int iterations) { max_iterations_ = iterations; }

 private:
  struct Node {
    PointState point;
    double rest_yaw = 0.0;
    int parent = -1;
    RootSegment edge;  ///< start tree: parent -> node; goal tree: node -> parent
    ob::State* state = nullptr;
  };
  using Tree = std::vector<Node>;

  /// One tree's growth towards a sample: the new node (-1 when the tree did not grow) and whether
  /// it is the sample itself (the whole steered piece was valid).
  struct Extension {
    int node = -1;
    bool reached = false;
  };

  /// The piece from the start straight to the goal: the path when it is valid whole; otherwise
  /// its valid prefix joins the start tree (when both ends have the same rest yaw) and nullopt.
  std::optional<RootPath> ConnectDirectly(double rest_start, double rest_goal);
  /// Steers from the start tree's state nearest to `target` towards it and keeps the valid prefix.
  Extension ExtendStartTree(const PointState& target, double rest_start);
  /// Steers from `target` to the goal tree's state nearest to it and keeps the valid suffix.
  Extension ExtendGoalTree(const PointState& target, double rest_goal);
  /// The trees joined by one more valid piece: from the new start-tree state to the nearest
  /// goal-tree state, else from the nearest start-tree state to the new goal-tree state.
  std::optional<RootPath> Join(const Extension& from_start, const Extension& from_goal, double rest_start,
                               double rest_goal) const;
  /// Records the tree sizes and hands `path` to the problem definition as the exact solution.
  ob::PlannerStatus AddSolution(RootPath path);
  int Nearest(const Tree& tree, const PointState& target, bool towards_target) const;
  int AddNode(Tree& tree, const PointState& point, double rest_yaw, int parent, const RootSegment& edge);
  RootPath Chain(int start_node, const std::optional<RootSegment>& bridge, int goal_node) const;
  bool Compatible(const PointState& point, double rest_a, double rest_b) const;
  void FreeTrees();

  const KinodynamicMotionValidator* validator_;
  SamplerSettings sampler_settings_;
  const std::vector<AffordanceSurface>* surfaces_;
  const ReachabilityValidityChecker* validity_;
  ReachabilityChecker* checker_;
  unsigned seed_;
  Tree start_tree_;
  Tree goal_tree_;
  BiRrtStats stats_;
  int max_iterations_ = std::numeric_limits<int>::max();
};

}  // namespace rbcp::detail
